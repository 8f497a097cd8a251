// The H.264 path in the page: access units (server/video/access_unit_wire.hpp: a 28-byte "LDH1"
// header, then Annex-B) decoded by WebCodecs' VideoDecoder with optimizeForLatency and drawn on a
// canvas. The decoder is configured from the first IDR's SPS (codec "avc1.PPCCLL"); until then, and
// after an error or a backlog, delta frames are dropped up to the next IDR. The server moves a viewer
// between the drone's stream and its shared low rendition at an IDR of the one it moves to (byte 22
// of the header): the decoder is configured anew there, from that IDR's SPS.
export const LDH1_HEADER_BYTES = 28;
const MAX_DECODE_QUEUE = 8;  // units waiting in the decoder before the page drops to the next IDR

export function h264Available() {
  return typeof window.VideoDecoder === 'function' && typeof window.EncodedVideoChunk === 'function';
}

export function parseAccessUnit(buffer) {
  const dv = new DataView(buffer);
  if (buffer.byteLength < LDH1_HEADER_BYTES || dv.getUint32(0, true) !== 0x3148444c) return null;  // "LDH1"
  const bytes = dv.getUint32(24, true);
  if (bytes !== buffer.byteLength - LDH1_HEADER_BYTES) return null;
  return {
    frame: dv.getUint32(4, true), captureMs: dv.getFloat64(8, true), camera: dv.getUint8(16),
    keyframe: (dv.getUint8(17) & 1) === 1, width: dv.getUint16(18, true), height: dv.getUint16(20, true),
    rendition: dv.getUint8(22) === 1 ? 'low' : 'source',
    data: new Uint8Array(buffer, LDH1_HEADER_BYTES),
  };
}

// "avc1.PPCCLL" from the first SPS (NAL type 7) of an Annex-B access unit, or null.
export function codecFromSps(annexb) {
  for (let i = 0; i + 6 < annexb.length; ++i) {
    if (annexb[i] !== 0 || annexb[i + 1] !== 0 || annexb[i + 2] !== 1) continue;
    if ((annexb[i + 3] & 0x1f) !== 7) continue;
    const hex = (v) => v.toString(16).padStart(2, '0');
    return 'avc1.' + hex(annexb[i + 4]) + hex(annexb[i + 5]) + hex(annexb[i + 6]);
  }
  return null;
}

export class H264Player {
  // onFrame(videoFrame, unit): draw it (and close it); onUnsupported(reason): give up on this path.
  constructor({onFrame, onUnsupported}) {
    this.onFrame = onFrame;
    this.onUnsupported = onUnsupported;
    this.decoder = null;
    this.codec = null;
    this.waitingForKey = true;
    this.checking = false;
    this.units = new Map();  // decode timestamp -> unit header, until its frame comes out
    this.errors = 0;
    this.dropped = 0;
    this.rendition = null;  // of the units the decoder was configured for
  }

  async push(unit) {
    if (this.checking) return;
    if (this.decoder && unit.keyframe && unit.rendition !== this.rendition) this.close();  // another stream from here
    if (!this.decoder) {
      if (!unit.keyframe) return;
      this.checking = true;
      const ok = await this.configure(unit);
      this.checking = false;
      if (!ok) return;
    }
    if (this.decoder.decodeQueueSize > MAX_DECODE_QUEUE) this.waitingForKey = true;  // the page lags
    if (this.waitingForKey && !unit.keyframe) { this.dropped++; return; }
    this.waitingForKey = false;
    this.units.set(unit.frame, unit);
    this.decoder.decode(new EncodedVideoChunk({type: unit.keyframe ? 'key' : 'delta', timestamp: unit.frame, data: unit.data}));
  }

  async configure(unit) {
    this.codec = codecFromSps(unit.data);
    this.rendition = unit.rendition;
    if (!this.codec) { this.onUnsupported('no SPS in the first IDR'); return false; }
    const config = {codec: this.codec, optimizeForLatency: true};
    let support;
    try { support = await VideoDecoder.isConfigSupported(config); } catch (e) { support = {supported: false}; }
    if (!support.supported) { this.onUnsupported(`H.264 ${this.codec} not supported by this browser`); return false; }
    this.decoder = new VideoDecoder({
      output: (frame) => {
        const u = this.units.get(frame.timestamp);
        this.units.delete(frame.timestamp);
        for (const k of this.units.keys()) if (k < frame.timestamp) this.units.delete(k);
        this.onFrame(frame, u);
      },
      error: (e) => this.failed(e),
    });
    this.decoder.configure(config);
    return true;
  }

  failed(e) {
    // A decode error closes the decoder: make a new one at the next IDR; give up after repeated errors.
    this.decoder = null;
    this.units.clear();
    this.waitingForKey = true;
    if (++this.errors >= 3) this.onUnsupported(`the decoder failed ${this.errors} times (${e.message})`);
  }

  close() {
    if (this.decoder && this.decoder.state !== 'closed') this.decoder.close();
    this.decoder = null;
    this.units.clear();
    this.waitingForKey = true;
  }
}
