// The top-down map of the lab: the room outline as the lab file states it (walls, benches, the base
// with its platform, the instruments with the way their panels face), the SLAM map's points (the
// server sends them in their own "slam_map" message about once a second, placed in the world and
// decimated), the teacher where face-follow has placed them, the drone's estimate coloured by its
// localization source, the set point in cyan and, in the simulated lab, the truth as a grey outline.
// World x (forward from the base) is up on the map, world y (left) is left.
const DESIRED = '#00c8c8';
const TRUTH = '#888';
const SLAM_POINT = '#6a6a6a';

export class MapView {
  constructor(canvas) {
    this.canvas = canvas;
    this.lab = null;          // hello's "lab": room, benches, platform, base (null: unknown)
    this.instruments = [];    // hello's "instruments"
    this.slamPoints = [];     // [[x, y], ...] world m
    this.slamRevision = 0;
  }

  setLab(lab, instruments) {
    this.lab = lab || null;
    this.instruments = instruments || [];
  }

  setSlamMap(msg) {
    this.slamPoints = msg.points || [];
    this.slamRevision = msg.revision;
  }

  // The world box the map shows: the room when the lab file gives it, else what there is to show.
  extent(m) {
    if (this.lab) {
      const r = this.lab.room;
      return {x0: r.min[0], y0: r.min[1], x1: r.max[0], y1: r.max[1]};
    }
    const pts = [[0, 0], [m.pose.x, m.pose.y], ...this.instruments.map((i) => [i.x, i.y])];
    let half = 3;
    for (const [x, y] of pts) half = Math.max(half, Math.abs(x) + 0.5, Math.abs(y) + 0.5);
    return {x0: -half, y0: -half, x1: half, y1: half};
  }

  draw(m) {
    if (!m) return;
    const g = this.canvas.getContext('2d');
    const w = this.canvas.width, h = this.canvas.height;
    g.clearRect(0, 0, w, h);
    const e = this.extent(m);
    const pad = 8;
    const s = Math.min((w - 2 * pad) / (e.y1 - e.y0), (h - 2 * pad) / (e.x1 - e.x0));
    const cu = w / 2, cv = h / 2, mx = (e.x0 + e.x1) / 2, my = (e.y0 + e.y1) / 2;
    const P = (x, y) => [cu - (y - my) * s, cv - (x - mx) * s];
    this.drawGrid(g, e, P, w, h);
    if (this.lab) this.drawOutline(g, P);
    g.fillStyle = SLAM_POINT;
    for (const [x, y] of this.slamPoints) { const [u, v] = P(x, y); g.fillRect(u - 1, v - 1, 2, 2); }
    this.drawMarkers(g, m, P);
    this.drawDrone(g, m, P);
  }

  drawGrid(g, e, P, w, h) {
    g.strokeStyle = '#eee'; g.lineWidth = 1;
    for (let y = Math.ceil(e.y0); y <= e.y1; ++y) { const [u] = P(0, y); g.beginPath(); g.moveTo(u, 0); g.lineTo(u, h); g.stroke(); }
    for (let x = Math.ceil(e.x0); x <= e.x1; ++x) { const [, v] = P(x, 0); g.beginPath(); g.moveTo(0, v); g.lineTo(w, v); g.stroke(); }
  }

  drawOutline(g, P) {
    const rect = (f) => {
      const [u0, v0] = P(f.max[0], f.max[1]), [u1, v1] = P(f.min[0], f.min[1]);
      return [u0, v0, u1 - u0, v1 - v0];
    };
    g.strokeStyle = '#333'; g.lineWidth = 3;
    g.strokeRect(...rect(this.lab.room));  // the walls
    g.fillStyle = '#e8dcc4'; g.strokeStyle = '#a08c64'; g.lineWidth = 1;
    for (const b of this.lab.benches) { const r = rect(b); g.fillRect(...r); g.strokeRect(...r); }
    g.fillStyle = '#d8d8a8'; g.strokeStyle = '#884';
    const p = rect(this.lab.platform); g.fillRect(...p); g.strokeRect(...p);
    // Each panel as a bar across its width, with a tick the way it faces.
    g.strokeStyle = '#1060ff';
    for (const i of this.instruments) {
      const f = i.facing_rad || 0, half = i.width_m / 2;
      const [a0, b0] = P(i.x - Math.sin(f) * half, i.y + Math.cos(f) * half);
      const [a1, b1] = P(i.x + Math.sin(f) * half, i.y - Math.cos(f) * half);
      const [c0, c1] = P(i.x, i.y), [d0, d1] = P(i.x + Math.cos(f) * 0.25, i.y + Math.sin(f) * 0.25);
      g.lineWidth = 4; g.beginPath(); g.moveTo(a0, b0); g.lineTo(a1, b1); g.stroke();
      g.lineWidth = 1.5; g.beginPath(); g.moveTo(c0, c1); g.lineTo(d0, d1); g.stroke();
    }
  }

  // Labels go right of their marker, else left, below or above, wherever they overlap no label
  // placed before (instruments side by side on a bench would otherwise print over each other).
  drawMarkers(g, m, P) {
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
    const base = this.lab ? this.lab.base : {x: 0, y: 0};
    label(base.x, base.y, 'base', '#884');
    for (const i of this.instruments) label(i.x, i.y, i.name || i.id, '#1060ff');
    if (m.teacher) label(m.teacher[0], m.teacher[1], 'teacher', '#ff9000');
    if (m.desired) { const [u, v] = P(m.desired.x, m.desired.y); g.strokeStyle = DESIRED; g.lineWidth = 2; g.strokeRect(u - 6, v - 6, 12, 12); }
  }

  drawDrone(g, m, P) {
    const arrow = (pose) => {
      const [u, v] = P(pose.x, pose.y), yaw = pose.yaw;
      g.beginPath();
      g.moveTo(u - Math.sin(yaw) * 12, v - Math.cos(yaw) * 12);
      g.lineTo(u - Math.sin(yaw + 2.5) * 8, v - Math.cos(yaw + 2.5) * 8);
      g.lineTo(u - Math.sin(yaw - 2.5) * 8, v - Math.cos(yaw - 2.5) * 8);
      g.closePath();
    };
    if (m.ground_truth) {  // the simulated lab's truth: a grey outline under the estimate
      g.strokeStyle = TRUTH; g.lineWidth = 1.5; arrow(m.ground_truth); g.stroke();
    }
    g.fillStyle = m.source_colour; arrow(m.pose); g.fill();
  }
}
