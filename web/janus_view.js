// The video through Janus (docs/web.md "Many viewers and several labs"): the lab's H.264 as the
// server forwards it (RTP to a Janus streaming mount point) reaches this page over WebRTC, and the
// overlay geometry over the same mount point's data channel (serve --geometry-udp: LaboDrone sends
// it once for every viewer). Until the data channel delivers, or when it falls silent, the geometry
// comes over LaboDrone's WebSocket instead (subscribe "geometry"). Each decoded frame is
// matched to its geometry by RTP timestamp: the server stamps a frame captured at capture_ms with
// round(capture_ms * 90) mod 2^32 (server/video/rtp_h264_packetizer.hpp), and Chromium reports the
// timestamp of each WebRTC frame it presents (requestVideoFrameCallback's rtpTimestamp). Janus
// rewrites timestamps by a constant offset per viewer (it keeps them continuous across source
// changes), so the page learns that offset (RtpOffset) and matches exactly once it is known.
// janus.js and adapter.js are Debian's (libjs-janus-gateway, libjs-webrtc-adapter), served from
// web/vendor/ (links to /usr/share/javascript). Any failure (no lab directory entry, no library, no
// Janus, no frame within FIRST_FRAME_TIMEOUT_MS) hands the video back to the WebSocket paths.
const FIRST_FRAME_TIMEOUT_MS = 6000;
const OFFSET_VOTES = 3;        // frames that must agree on an offset before it is used
const OFFSET_LOST_FRAMES = 30;  // frames without a match after which the offset is learnt again
const DATA_SILENT_MS = 2000;    // data channel without geometry this long: back to the WebSocket's

export function rtpTimestampOf(captureMs) {
  return Math.round(captureMs * 90) % 4294967296;
}

// The constant difference between the timestamps Janus delivers and the server's: the offset that
// the most recent frames agree on, each frame voting for its difference to every geometry waiting.
export class RtpOffset {
  constructor() { this.reset(); }
  reset() { this.offset = null; this.votes = new Map(); this.misses = 0; this.last = null; }

  // The geometry of the frame with RTP timestamp `rtp` among `geometries`, or null.
  match(rtp, geometries) {
    if (this.offset !== null) {
      const want = (rtp - this.offset + 4294967296) % 4294967296;
      for (const g of geometries) if (rtpTimestampOf(g.capture_ms) === want) { this.misses = 0; this.last = g; return g; }
      if (++this.misses >= OFFSET_LOST_FRAMES) this.reset();
      return null;
    }
    const votes = new Map();
    for (const g of geometries) {
      const d = (rtp - rtpTimestampOf(g.capture_ms) + 4294967296) % 4294967296;
      votes.set(d, (this.votes.get(d) || 0) + 1);
    }
    this.votes = votes;  // only differences every recent frame shares survive
    for (const [d, n] of votes) if (n >= OFFSET_VOTES) { this.offset = d; return this.match(rtp, geometries); }
    return null;
  }
}

// A frame's geometry from its data-channel messages (server/video/geometry_datagrams.hpp): each is
// "LDG1 <frame> <part> <count>\n" and a part of the JSON, in order (Janus's data channel is reliable
// and ordered); a frame whose parts stop coming is dropped when the next frame starts.
export class GeometryParts {
  constructor() { this.frame = null; this.parts = []; this.decoder = new TextDecoder(); }

  // The frame's geometry once its last part is in, else null (also for a malformed message).
  // Janus delivers the datagrams as text or as binary messages (ArrayBuffer) by its version; each
  // part is whole UTF-8 either way.
  add(message) {
    const text = message instanceof ArrayBuffer ? this.decoder.decode(message) : message;
    const newline = typeof text === 'string' ? text.indexOf('\n') : -1;
    const header = newline > 0 ? text.slice(0, newline).split(' ') : [];
    if (header.length !== 4 || header[0] !== 'LDG1') return null;
    const [frame, part, count] = header.slice(1).map(Number);
    if (part === 0) { this.frame = frame; this.parts = []; }
    if (frame !== this.frame || part !== this.parts.length) return null;
    this.parts.push(text.slice(newline + 1));
    if (this.parts.length < count) return null;
    this.frame = null;
    try { return JSON.parse(this.parts.join('')); } catch (e) { return null; }
  }
}

function loadScript(src) {
  return new Promise((resolve, reject) => {
    const s = document.createElement('script');
    s.src = src;
    s.onload = resolve;
    s.onerror = () => reject(new Error(`${src} did not load`));
    document.head.append(s);
  });
}

// This lab's Janus mount point from GET /api/labs ({url, mountpoint}), or a reason why not.
export async function janusTarget(search = window.location.search) {
  const wanted = new URLSearchParams(search).get('video');
  if (wanted === 'direct') return {reason: 'the direct WebSocket path was asked for (?video=direct)'};
  if (typeof window.RTCPeerConnection !== 'function') return {reason: 'no WebRTC in this browser'};
  try {
    const r = await fetch('/api/labs', {credentials: 'same-origin'});
    if (!r.ok) return {reason: `no lab directory (${r.status})`};
    const dir = await r.json();
    const self = (dir.labs || []).find((l) => l.id === dir.self);
    if (!self || !self.janus) return {reason: 'this lab has no Janus mount point'};
    return {url: self.janus.url.replace('{host}', window.location.hostname), mountpoint: self.janus.mountpoint};
  } catch (e) {
    return {reason: 'lab directory unreadable: ' + e.message};
  }
}

export class JanusView {
  // view: the VideoView (its canvas, geometry map, overlay switches and frame accounting);
  // onFail(reason): Janus is unusable, take another path.
  constructor(doc, view, target, onFail) {
    Object.assign(this, {doc, view, target, onFail});
    this.closed = false;
    this.video = doc.createElement('video');
    Object.assign(this.video, {muted: true, autoplay: true, playsInline: true});
    // In the document (a detached or hidden element may not be decoded), but invisible: the canvas shows it.
    this.video.style.cssText = 'position:absolute;left:0;top:0;width:2px;height:2px;opacity:0;pointer-events:none';
    doc.body.append(this.video);
    this.matched = 0;
    this.unmatched = 0;
    this.offset = new RtpOffset();
    this.parts = new GeometryParts();
    this.dataGeometryAt = null;  // when the data channel last delivered a geometry (null: it does not)
  }

  async start() {
    try {
      if (!window.Janus) {
        await loadScript('/vendor/adapter.js');
        await loadScript('/vendor/janus.js');
      }
      await new Promise((resolve) => window.Janus.init({debug: false, callback: resolve}));
      if (!window.Janus.isWebrtcSupported()) throw new Error('janus.js finds no WebRTC');
      await this.connect();
    } catch (e) {
      this.fail(e.message || String(e));
      return;
    }
    this.firstFrameTimer = setTimeout(() => this.fail(`no frame from Janus within ${FIRST_FRAME_TIMEOUT_MS / 1000} s`),
                                      FIRST_FRAME_TIMEOUT_MS);
  }

  connect() {
    return new Promise((resolve, reject) => {
      this.session = new window.Janus({
        server: this.target.url,
        error: (e) => (this.handle ? this.fail('Janus: ' + e) : reject(new Error('Janus at ' + this.target.url + ': ' + e))),
        success: () => this.session.attach({
          plugin: 'janus.plugin.streaming',
          error: (e) => reject(new Error('streaming plugin: ' + e)),
          success: (handle) => {
            this.handle = handle;
            handle.send({message: {request: 'watch', id: this.target.mountpoint}});
            resolve();
          },
          onmessage: (msg, jsep) => this.onMessage(msg, jsep),
          onremotetrack: (track, mid, on) => { if (on && track.kind === 'video') this.play(track); },
          ondata: (data) => this.onData(data),
        }),
      });
    });
  }

  onMessage(msg, jsep) {
    if (msg.error) return this.fail(`mount point ${this.target.mountpoint}: ${msg.error}`);
    if (!jsep) return;
    this.handle.createAnswer({
      jsep,
      tracks: [{type: 'audio', recv: false}, {type: 'video', recv: true}, {type: 'data', recv: false}],
      success: (answer) => this.handle.send({message: {request: 'start'}, jsep: answer}),
      error: (e) => this.fail('WebRTC answer: ' + (e.message || e)),
    });
  }

  // A data-channel message: a frame's geometry once complete. The first one moves the WebSocket to
  // the 'none' path (no per-viewer geometry from LaboDrone).
  onData(data) {
    const geometry = this.parts.add(data);
    if (!geometry) return;
    this.view.onGeometry(geometry);
    if (this.dataGeometryAt === null) this.view.geometryFrom('data channel');
    this.dataGeometryAt = performance.now();
  }

  play(track) {
    this.video.srcObject = new MediaStream([track]);
    this.video.play().catch(() => {});
    if (this.playing) return;  // Janus may announce the track again (renegotiation): one frame loop
    this.playing = true;
    let last = -1;
    const onFrame = (now, meta) => {
      if (this.closed) return;
      if (meta.presentedFrames !== last) this.draw(meta);
      last = meta.presentedFrames;
      this.video.requestVideoFrameCallback(onFrame);
    };
    this.video.requestVideoFrameCallback(onFrame);
  }

  // One presented frame: on the canvas with the overlays of the same frame, found by RTP timestamp.
  draw(meta) {
    clearTimeout(this.firstFrameTimer);
    if (this.dataGeometryAt !== null && performance.now() - this.dataGeometryAt > DATA_SILENT_MS) {
      this.dataGeometryAt = null;  // the mount point's data went silent: the WebSocket's geometry again
      this.view.geometryFrom('websocket');
    }
    const v = this.view, canvas = v.canvas;
    canvas.getContext('2d').drawImage(this.video, 0, 0, canvas.width, canvas.height);
    const match = this.offset.match(meta.rtpTimestamp, [...v.geometry.values()]);
    if (match) {
      for (const k of v.geometry.keys()) if (k <= match.frame) v.geometry.delete(k);
      v.drawOverlays(match);
      v.stats.janusMatched = ++this.matched;
      v.shown(match.frame, match.capture_ms);
      return;
    }
    // Its geometry is late (a busy page reads the WebSocket after the frame is decoded) or lost: the
    // frame is shown without overlays, its capture time told by its timestamp once the offset is known.
    v.stats.overlaysDrawn = [];
    v.stats.janusUnmatched = ++this.unmatched;
    const newest = [...v.geometry.values()].pop() || this.offset.last;
    if (this.offset.offset === null || !newest) return;
    const want = (meta.rtpTimestamp - this.offset.offset + 4294967296) % 4294967296;
    const ticks = ((want - rtpTimestampOf(newest.capture_ms) + 6442450944) % 4294967296) - 2147483648;  // signed
    v.shown(-1, newest.capture_ms + ticks / 90);
  }

  fail(reason) {
    if (this.closed) return;
    this.close();
    this.onFail(reason);
  }

  close() {
    this.closed = true;
    clearTimeout(this.firstFrameTimer);
    try { if (this.handle) this.handle.detach(); } catch (e) { /* the session may be gone already */ }
    try { if (this.session) this.session.destroy({cleanupHandles: true}); } catch (e) { /* likewise */ }
    this.video.srcObject = null;
    this.video.remove();
  }
}
