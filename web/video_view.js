// The live video on the lab page, by one of three paths (docs/web.md "WebSocket protocol"):
//  - janus: when this lab has a Janus mount point (janus_view.js), the drone's stream over WebRTC
//    from Janus, the overlays drawn here from the geometry of the mount point's data channel (or the
//    WebSocket's until that delivers); else, or when Janus fails, one of the WebSocket's own:
//  - h264: the drone's own stream decoded in the page (WebCodecs), the overlays drawn here from the
//    geometry sent with each frame, each group switchable; on a link too slow for the drone's
//    stream, the server's shared low rendition instead (chosen by the server, or by the viewer);
//  - jpeg: frames with the overlays drawn in by the server; chosen when the browser has no
//    VideoDecoder or cannot decode the stream's H.264 profile.
// Measures the glass-to-browser latency: the frame's capture time (server clock) to the moment the
// frame and its overlays are on the canvas (same machine or synchronized clocks).
import {H264Player, h264Available, parseAccessUnit} from './h264_player.js';
import {JanusView, janusTarget} from './janus_view.js';
import {OVERLAY_GROUPS, paintOverlays} from './overlay_painter.js';
import {ReadingView} from './reading_view.js';
import {ReplayView, isReplayFrame} from './replay_view.js';

const LATENCY_WINDOW = 1800;  // a minute at 30 frames/s

export class VideoView {
  // send(obj): a message to the server; stats: the object tests read (window.labodrone).
  constructor(doc, send, stats) {
    this.doc = doc;
    this.canvas = doc.getElementById('video');
    this.send = send;
    this.stats = stats;
    this.geometry = new Map();  // frame number -> overlay geometry, until that frame is drawn
    this.latencies = [];
    this.frames = 0;
    this.player = null;
    this.janus = null;
    this.janusTarget = janusTarget();  // asked once; start() waits for it
    this.reading = new ReadingView(doc, stats);
    this.replay = new ReplayView(doc.getElementById('replay'), stats);
    this.enabled = {};
    for (const group of OVERLAY_GROUPS) {
      const box = doc.getElementById('overlay-' + group);
      this.enabled[group] = box.checked;
      box.addEventListener('change', () => { this.enabled[group] = box.checked; });
    }
    this.cameraChoice = doc.getElementById('video-camera');
    this.cameraChoice.addEventListener('change', () => send({type: 'command', command: 'select_camera', camera: this.cameraChoice.value}));
    this.renditionChoice = doc.getElementById('video-rendition-choice');
    this.renditionChoice.addEventListener('change', () => this.chooseRendition(this.renditionChoice.value));
    Object.assign(stats, {camera: null, videoInfo: null, rendition: null, renditionTarget: null, renditionReason: '', linkKbps: null,
                          renditionFrames: {source: 0, low: 0}});
    Object.assign(stats, {videoPath: null, videoPathReason: '', codec: null, framesDecoded: 0, lastFrameNumber: -1,
                          latencyMedianMs: null, latencyP95Ms: null, videoBytes: 0, overlaysDrawn: [], unitsDropped: 0,
                          // Restart the latency window (a measurement leaves the start-up out).
                          resetLatencies: () => { this.latencies = []; },
                          latencySummary: () => this.latencySummary()});
  }

  // On every (re)connection: Janus when this lab has a mount point, else (or when it fails) the
  // H.264 path when the browser has WebCodecs, else JPEG.
  async start() {
    this.describeDrone();
    const target = await this.janusTarget;
    if (target.url) this.choose('janus', `mount point ${target.mountpoint}`, target);
    else this.startDirect(target.reason);
  }

  startDirect(why) {
    this.stats.janusReason = why;
    if (h264Available()) this.choose('h264', 'WebCodecs');
    else this.choose('jpeg', 'no WebCodecs VideoDecoder in this browser');
  }

  choose(path, reason, janusTarget = null) {
    if (this.player) this.player.close();
    if (this.janus) this.janus.close();
    this.janus = path === 'janus' ? new JanusView(this.doc, this, janusTarget, (why) => this.startDirect(why)) : null;
    this.player = path === 'h264' ? new H264Player({
      onFrame: (frame, unit) => this.drawDecoded(frame, unit),
      onUnsupported: (why) => this.choose('jpeg', why),
    }) : null;
    this.geometry.clear();
    Object.assign(this.stats, {videoPath: path, videoPathReason: reason, geometrySource: path === 'janus' ? 'websocket' : null});
    this.doc.getElementById('video-path').textContent = {
      janus: `H.264 through Janus (WebRTC, ${reason}); overlays drawn here`,
      h264: 'H.264, decoded here (WebCodecs); overlays drawn here' + (this.stats.janusReason ? ` (not Janus: ${this.stats.janusReason})` : ''),
    }[path] || `JPEG, overlays drawn by the server (${reason})`;
    for (const group of OVERLAY_GROUPS) this.doc.getElementById('overlay-' + group).disabled = path === 'jpeg';
    this.renditionChoice.disabled = path !== 'h264';
    this.send(path === 'h264' ? {type: 'subscribe', video: path, rendition: this.renditionChoice.value}
                              : {type: 'subscribe', video: path === 'janus' ? 'geometry' : path});
    if (this.janus) this.janus.start();
  }

  // What the drone's video offers (GET /api/video): a drone without a bottom camera says so here.
  async describeDrone() {
    const reply = await fetch('/api/video');
    if (!reply.ok) return;
    const info = await reply.json();
    this.stats.videoInfo = info;
    const bottom = this.cameraChoice.querySelector('option[value=bottom]');
    bottom.disabled = !info.bottom_camera;
    this.doc.getElementById('video-camera-note').textContent = info.bottom_camera ? '' : info.no_bottom_camera;
  }

  // The camera of the frame on the canvas.
  showCamera(camera) {
    const name = camera === 1 ? 'bottom' : 'front';
    if (this.stats.camera === name) return;
    this.stats.camera = name;
    this.doc.getElementById('video-camera-shown').textContent = name;
  }

  // auto (the server follows this viewer's link), source (the drone's stream) or low.
  chooseRendition(choice) {
    if (this.stats.videoPath === 'h264') this.send({type: 'subscribe', video: 'h264', rendition: choice});
  }

  // The server's word on this viewer's rendition: where it moves (at that rendition's next IDR), why,
  // and what the link carried.
  onRendition(msg) {
    Object.assign(this.stats, {renditionTarget: msg.rendition, renditionReason: msg.reason, linkKbps: msg.throughput_kbps});
    this.showRendition();
  }

  showRendition() {
    const s = this.stats;
    const name = (r) => r === 'low' ? 'the shared low rendition' : r === 'source' ? "the drone's stream" : '–';
    let text = name(s.rendition);
    if (s.renditionTarget && s.renditionTarget !== s.rendition) text += `, moving to ${name(s.renditionTarget)}`;
    if (s.renditionReason) text += ` (${s.renditionReason})`;
    if (s.linkKbps !== null) text += ` · link ${s.linkKbps} kbit/s`;
    this.doc.getElementById('video-rendition').textContent = text;
  }

  // Where the Janus path's geometry comes from: the mount point's data channel (the WebSocket then
  // carries no video at all: 'none') or the WebSocket ('geometry').
  geometryFrom(source) {
    if (this.stats.videoPath !== 'janus') return;
    this.stats.geometrySource = source;
    this.send({type: 'subscribe', video: source === 'data channel' ? 'none' : 'geometry'});
  }

  onGeometry(msg) {
    this.geometry.set(msg.frame, msg);
    if (this.geometry.size > 64) this.geometry.delete(this.geometry.keys().next().value);  // units never decoded
  }

  async onBinary(buffer) {
    if (isReplayFrame(buffer)) return this.replay.show(buffer);
    if (buffer.byteLength >= 24 && new DataView(buffer).getUint32(0, true) === 0x3152444c) return this.reading.show(buffer);  // "LDR1"
    this.stats.videoBytes += buffer.byteLength;
    if (this.stats.videoPath === 'h264') {
      const unit = parseAccessUnit(buffer);
      if (unit && this.player) await this.player.push(unit);
      if (this.player) { this.stats.codec = this.player.codec; this.stats.unitsDropped = this.player.dropped; }
      return;
    }
    await this.drawJpeg(buffer);
  }

  drawDecoded(frame, unit) {
    const g = this.canvas.getContext('2d');
    g.drawImage(frame, 0, 0, this.canvas.width, this.canvas.height);
    frame.close();
    if (!unit) return;
    const geometry = this.geometry.get(unit.frame);
    for (const k of this.geometry.keys()) if (k <= unit.frame) this.geometry.delete(k);
    this.stats.overlaysDrawn = geometry ? this.drawOverlays(geometry) : [];
    this.stats.renditionFrames[unit.rendition]++;
    this.showCamera(unit.camera);
    if (this.stats.rendition !== unit.rendition) {
      this.stats.rendition = unit.rendition;
      this.showRendition();
    }
    this.shown(unit.frame, unit.captureMs);
  }

  drawOverlays(geometry) {
    return (this.stats.overlaysDrawn = paintOverlays(this.canvas, geometry, this.enabled));
  }

  async drawJpeg(buffer) {
    const dv = new DataView(buffer);
    if (buffer.byteLength < 24 || dv.getUint32(0, true) !== 0x3156444c) return;  // "LDV1"
    const bitmap = await createImageBitmap(new Blob([new Uint8Array(buffer, 24)], {type: 'image/jpeg'}));
    this.canvas.getContext('2d').drawImage(bitmap, 0, 0, this.canvas.width, this.canvas.height);
    bitmap.close();
    this.showCamera(dv.getUint8(16));
    this.shown(dv.getUint32(4, true), dv.getFloat64(8, true));
  }

  // A frame is on the canvas: count it and its glass-to-browser latency.
  shown(frameNumber, captureMs) {
    const latency = Date.now() - captureMs;
    this.latencies.push(latency);
    if (this.latencies.length > LATENCY_WINDOW) this.latencies.shift();
    Object.assign(this.stats, {framesDecoded: this.stats.framesDecoded + 1, lastFrameNumber: frameNumber});
    this.doc.getElementById('frame-number').textContent = frameNumber;
    this.doc.getElementById('latency').textContent = latency.toFixed(0);
    this.frames++;
  }

  // Median and 95th percentile of the latencies in the window.
  latencySummary() {
    const sorted = [...this.latencies].sort((a, b) => a - b);
    const at = (p) => sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))];
    return {median: at(0.5), p95: at(0.95), frames: sorted.length};
  }

  // Frames drawn since the last call (for the fps display, once a second); the latency shown.
  takeFrameCount() {
    const n = this.frames;
    this.frames = 0;
    if (this.latencies.length) {
      const {median, p95} = this.latencySummary();
      Object.assign(this.stats, {latencyMedianMs: median, latencyP95Ms: p95});
      this.doc.getElementById('latency-median').textContent = median.toFixed(0);
    }
    return n;
  }
}
