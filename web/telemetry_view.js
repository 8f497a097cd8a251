// Telemetry plots: x, y, z, yaw over the last minute, estimated coloured by localization source,
// desired in cyan, the simulated lab's truth dashed grey, like the paper's Figs 5-9. The map of the
// room is map_view.js.
const WINDOW_S = 60;
const DESIRED = '#00c8c8';
const TRUTH = '#888';

export class TelemetryView {
  constructor(doc) {
    this.samples = [];  // {t, pose, desired, truth, colour}
    this.plots = ['x', 'y', 'z', 'yaw'].map((k) => ({key: k, canvas: doc.getElementById('plot-' + k)}));
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
}
