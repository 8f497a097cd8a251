// Telemetry plots (x, y, z, yaw over the last minute, estimated coloured by localization source,
// desired in cyan, the simulated lab's truth dashed grey, like the paper's Figs 5-9) and the
// top-down map of the room.
const WINDOW_S = 60;
const DESIRED = '#00c8c8';
const TRUTH = '#888';

export class TelemetryView {
  constructor(doc) {
    this.samples = [];  // {t, pose, desired, truth, colour}
    this.plots = ['x', 'y', 'z', 'yaw'].map((k) => ({key: k, canvas: doc.getElementById('plot-' + k)}));
    this.map = doc.getElementById('map');
    this.instruments = [];
    this.last = null;
  }

  add(msg) {
    this.samples.push({t: msg.t, pose: msg.pose, desired: msg.desired, truth: msg.ground_truth, colour: msg.source_colour});
    const cutoff = msg.t - WINDOW_S;
    while (this.samples.length && this.samples[0].t < cutoff) this.samples.shift();
    this.last = msg;
  }

  draw() {
    if (!this.samples.length) return;
    for (const p of this.plots) this.drawPlot(p);
    this.drawMap();
  }

  drawPlot({key, canvas}) {
    const g = canvas.getContext('2d');
    const w = canvas.width, h = canvas.height;
    g.clearRect(0, 0, w, h);
    const t1 = this.samples[this.samples.length - 1].t, t0 = t1 - WINDOW_S;
    let lo = Infinity, hi = -Infinity;
    for (const s of this.samples) {
      for (const v of [s.pose[key], s.desired ? s.desired[key] : undefined, s.truth ? s.truth[key] : undefined]) {
        if (v === undefined || !isFinite(v)) continue;
        lo = Math.min(lo, v); hi = Math.max(hi, v);
      }
    }
    if (hi - lo < 0.2) { const m = (hi + lo) / 2; lo = m - 0.1; hi = m + 0.1; }
    const X = (t) => ((t - t0) / WINDOW_S) * (w - 40) + 36;
    const Y = (v) => h - 4 - ((v - lo) / (hi - lo)) * (h - 8);
    g.fillStyle = '#444'; g.font = '10px sans-serif';
    g.fillText(key + (key === 'yaw' ? ' rad' : ' m'), 2, 10);
    g.fillText(hi.toFixed(2), 2, 22); g.fillText(lo.toFixed(2), 2, h - 4);
    g.lineWidth = 1.5; g.strokeStyle = TRUTH; g.setLineDash([4, 3]); g.beginPath();
    let pen = false;
    for (const s of this.samples) {
      if (!s.truth) { pen = false; continue; }
      if (pen) g.lineTo(X(s.t), Y(s.truth[key])); else g.moveTo(X(s.t), Y(s.truth[key]));
      pen = true;
    }
    g.stroke(); g.setLineDash([]);
    g.lineWidth = 2;
    for (let i = 1; i < this.samples.length; ++i) {
      const a = this.samples[i - 1], b = this.samples[i];
      if (a.desired && b.desired) {
        g.strokeStyle = DESIRED; g.beginPath();
        g.moveTo(X(a.t), Y(a.desired[key])); g.lineTo(X(b.t), Y(b.desired[key])); g.stroke();
      }
      g.strokeStyle = b.colour; g.beginPath();
      g.moveTo(X(a.t), Y(a.pose[key])); g.lineTo(X(b.t), Y(b.pose[key])); g.stroke();
    }
  }

  drawMap() {
    const g = this.map.getContext('2d');
    const w = this.map.width, h = this.map.height;
    g.clearRect(0, 0, w, h);
    const m = this.last;
    const pts = [[0, 0], [m.pose.x, m.pose.y], ...this.instruments.map((i) => [i.x, i.y])];
    if (m.teacher) pts.push(m.teacher);
    let half = 3;
    for (const [x, y] of pts) half = Math.max(half, Math.abs(x) + 0.5, Math.abs(y) + 0.5);
    const s = Math.min(w, h) / (2 * half);
    // World x forward is up on the map, world y left is left.
    const P = (x, y) => [w / 2 - y * s, h / 2 - x * s];
    g.strokeStyle = '#ddd'; g.lineWidth = 1;
    for (let v = -Math.floor(half); v <= half; ++v) {
      const [a] = P(0, v); g.beginPath(); g.moveTo(a, 0); g.lineTo(a, h); g.stroke();
      const [, b] = P(v, 0); g.beginPath(); g.moveTo(0, b); g.lineTo(w, b); g.stroke();
    }
    g.fillStyle = '#999';
    for (const [x, y] of m.slam_points || []) { const [u, v] = P(x, y); g.fillRect(u - 1, v - 1, 2, 2); }
    // Labels go right of their marker, else left, below or above, wherever they overlap no label
    // placed before (instruments side by side on a bench would otherwise print over each other).
    const placed = [];
    g.font = '11px sans-serif';
    const label = (x, y, text, colour) => {
      const [u, v] = P(x, y); g.fillStyle = colour; g.fillRect(u - 4, v - 4, 8, 8);
      const tw = g.measureText(text).width, th = 11;
      const spots = [[u + 6, v + 4], [u - 6 - tw, v + 4], [u - tw / 2, v + 16], [u - tw / 2, v - 8], [u + 6, v + 16], [u + 6, v - 8]];
      const free = ([x0, y0]) => placed.every((r) => x0 + tw < r[0] || x0 > r[0] + r[2] || y0 < r[1] - th || y0 - th > r[1]);
      const [lx, ly] = spots.find(free) || spots[0];
      placed.push([lx, ly, tw]);
      g.fillStyle = '#222'; g.fillText(text, lx, ly);
    };
    label(0, 0, 'base', '#884');
    for (const i of this.instruments) label(i.x, i.y, i.name || i.id, '#1060ff');
    if (m.teacher) label(m.teacher[0], m.teacher[1], 'teacher', '#ff9000');
    if (m.desired) { const [u, v] = P(m.desired.x, m.desired.y); g.strokeStyle = DESIRED; g.lineWidth = 2; g.strokeRect(u - 6, v - 6, 12, 12); }
    if (m.ground_truth) {  // the simulated lab's truth: a grey outline under the estimate
      const [tu, tv] = P(m.ground_truth.x, m.ground_truth.y), ty = m.ground_truth.yaw;
      g.strokeStyle = TRUTH; g.lineWidth = 1.5; g.beginPath();
      g.moveTo(tu - Math.sin(ty) * 12, tv - Math.cos(ty) * 12);
      g.lineTo(tu - Math.sin(ty + 2.5) * 8, tv - Math.cos(ty + 2.5) * 8);
      g.lineTo(tu - Math.sin(ty - 2.5) * 8, tv - Math.cos(ty - 2.5) * 8);
      g.closePath(); g.stroke();
    }
    const [u, v] = P(m.pose.x, m.pose.y);
    const yaw = m.pose.yaw;
    g.fillStyle = m.source_colour; g.beginPath();
    g.moveTo(u - Math.sin(yaw) * 12, v - Math.cos(yaw) * 12);
    g.lineTo(u - Math.sin(yaw + 2.5) * 8, v - Math.cos(yaw + 2.5) * 8);
    g.lineTo(u - Math.sin(yaw - 2.5) * 8, v - Math.cos(yaw - 2.5) * 8);
    g.closePath(); g.fill();
  }
}
