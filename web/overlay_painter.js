// Draws a frame's overlays from the geometry the server sends with each H.264 access unit
// (server/video/overlay_geometry.hpp), in the colours the server draws into JPEG frames
// (server/video/overlay_renderer.cpp): the tracked panel's and platform's outlines in cyan with
// their axes (x red, y green, z blue), the face mesh in yellow with orange points and its axes, the
// HUD strip, and the border and dot in the localization source's colour. Each group can be off.
export const OVERLAY_GROUPS = ['panel', 'platform', 'face', 'hud', 'border'];

const CYAN = 'rgb(0,255,255)';
const AXIS_COLOURS = {x: 'rgb(255,0,0)', y: 'rgb(0,200,0)', z: 'rgb(0,80,255)'};
const FACE_LINE = 'rgb(255,220,0)';
const FACE_POINT = 'rgb(255,160,0)';

const finite = (p) => Array.isArray(p) && Number.isFinite(p[0]) && Number.isFinite(p[1]);

function arrow(g, from, to, colour) {
  if (!finite(from) || !finite(to)) return;
  const [x0, y0] = from, [x1, y1] = to;
  const len = Math.hypot(x1 - x0, y1 - y0);
  if (len < 1) return;
  const tip = 0.15 * len, a = Math.atan2(y1 - y0, x1 - x0);
  g.strokeStyle = colour;
  g.lineWidth = 2;
  g.beginPath();
  g.moveTo(x0, y0); g.lineTo(x1, y1);
  g.moveTo(x1 - tip * Math.cos(a - Math.PI / 4), y1 - tip * Math.sin(a - Math.PI / 4)); g.lineTo(x1, y1);
  g.lineTo(x1 - tip * Math.cos(a + Math.PI / 4), y1 - tip * Math.sin(a + Math.PI / 4));
  g.stroke();
}

function axes(g, a) {
  if (!a || !finite(a.o)) return;
  for (const k of ['x', 'y', 'z']) arrow(g, a.o, a[k], AXIS_COLOURS[k]);
}

function outline(g, o) {
  if (!o || !Array.isArray(o.corners) || o.corners.length !== 4 || !o.corners.every(finite)) return false;
  g.strokeStyle = CYAN;
  g.lineWidth = 2;
  g.beginPath();
  o.corners.forEach(([x, y], i) => (i ? g.lineTo(x, y) : g.moveTo(x, y)));
  g.closePath();
  g.stroke();
  axes(g, o.axes);
  return true;
}

function face(g, f) {
  if (!f || !Array.isArray(f.points) || !f.points.length) return false;
  g.strokeStyle = FACE_LINE;
  g.lineWidth = 1;
  g.beginPath();
  for (const [i, j] of f.edges || []) {
    const a = f.points[i], b = f.points[j];
    if (finite(a) && finite(b)) { g.moveTo(a[0], a[1]); g.lineTo(b[0], b[1]); }
  }
  g.stroke();
  g.fillStyle = FACE_POINT;
  for (const p of f.points) if (finite(p)) { g.beginPath(); g.arc(p[0], p[1], 2, 0, 2 * Math.PI); g.fill(); }
  axes(g, f.axes);
  return true;
}

function hud(g, geometry, w) {
  const h = geometry.hud;
  if (!h) return false;
  g.fillStyle = '#000';
  g.fillRect(0, 0, w, 22);
  const sign = h.yaw_deg >= 0 ? '+' : '';
  g.fillStyle = '#fff';
  g.font = '12px sans-serif';
  g.fillText(`BAT ${Math.round(h.battery_percent)}%  ALT ${h.altitude_m.toFixed(2)}m  YAW ${sign}${Math.round(h.yaw_deg)}deg  ` +
             `LINK ${Math.round(h.link_quality * 100)}%  ${h.mission} ${h.stage}  [${geometry.source}]`, 6, 16);
  return true;
}

function border(g, geometry, w, h) {
  g.strokeStyle = geometry.source_colour;
  g.lineWidth = 6;
  g.strokeRect(0, 0, w, h);
  g.fillStyle = geometry.source_colour;
  g.beginPath(); g.arc(w - 14, 11, 7, 0, 2 * Math.PI); g.fill();
  g.strokeStyle = '#fff'; g.lineWidth = 1; g.stroke();
  return true;
}

// Draws the groups `enabled` has on, over the frame already on `canvas`; returns the groups drawn.
export function paintOverlays(canvas, geometry, enabled) {
  const g = canvas.getContext('2d');
  const sx = canvas.width / (geometry.width || canvas.width), sy = canvas.height / (geometry.height || canvas.height);
  const drawn = [];
  g.save();
  g.setTransform(sx, 0, 0, sy, 0, 0);
  const w = geometry.width || canvas.width, h = geometry.height || canvas.height;
  if (enabled.panel && outline(g, geometry.panel)) drawn.push('panel');
  if (enabled.platform && outline(g, geometry.platform)) drawn.push('platform');
  if (enabled.face && face(g, geometry.face)) drawn.push('face');
  if (enabled.border && border(g, geometry, w, h)) drawn.push('border');
  if (enabled.hud && hud(g, geometry, w)) drawn.push('hud');
  g.restore();
  return drawn;
}
