// The instrument reading view: while a panel is tracked, the server sends it a few times a second
// rectified to its template's front view ("LDR1": a 24-byte header like the JPEG frames', then a
// JPEG; server/video/panel_reading_view.hpp). Shown at its own resolution, so that the display and
// the labels can be read; hidden once no view came for two seconds.
const HIDE_AFTER_MS = 2000;

// The JPEG after a binary message's 24-byte header, drawn on `canvas` at the picture's own size.
export async function drawAtOwnSize(canvas, buffer) {
  const bitmap = await createImageBitmap(new Blob([new Uint8Array(buffer, 24)], {type: 'image/jpeg'}));
  canvas.width = bitmap.width;
  canvas.height = bitmap.height;
  canvas.getContext('2d').drawImage(bitmap, 0, 0);
  bitmap.close();
}

export class ReadingView {
  constructor(doc, stats) {
    this.section = doc.getElementById('reading');
    this.canvas = doc.getElementById('reading-view');
    this.caption = doc.getElementById('reading-caption');
    this.stats = stats;
    this.hideTimer = null;
    stats.readingViews = 0;
  }

  async show(buffer) {
    const dv = new DataView(buffer);
    await drawAtOwnSize(this.canvas, buffer);
    const ageMs = Date.now() - dv.getFloat64(8, true);
    this.caption.textContent = `frame ${dv.getUint32(4, true)}, ${this.canvas.width}×${this.canvas.height}, ${ageMs.toFixed(0)} ms old`;
    this.section.hidden = false;
    this.stats.readingViews++;
    clearTimeout(this.hideTimer);
    this.hideTimer = setTimeout(() => { this.section.hidden = true; }, HIDE_AFTER_MS);
  }
}
