// The admin page's metrics panel: /metrics (Prometheus text) polled, a few series kept for three
// minutes and drawn as small charts. Counters are shown as rates per second.
const kSeries = [
  {name: 'labodrone_ws_clients', label: 'WebSocket clients'},
  {name: 'labodrone_frames_published_total', label: 'frames published /s', rate: true},
  {name: 'labodrone_ws_bytes_out_total', label: 'kB/s out', rate: true, scale: 1e-3},
  {name: 'labodrone_commands_accepted_total', label: 'commands accepted /s', rate: true},
  {name: 'labodrone_commands_rejected_total', label: 'commands refused /s', rate: true},
  {name: 'labodrone_http_requests_total', label: 'HTTP requests /s', rate: true},
  {name: 'labodrone_queue_length', label: 'control queue'},
  {name: 'labodrone_battery_percent', label: 'battery %'},
  {name: 'labodrone_video_fps', label: 'video frames/s'},
];
const kKeepS = 180;

export function parsePrometheus(text) {
  const values = {};
  for (const line of text.split('\n')) {
    if (!line || line.startsWith('#')) continue;
    const [name, value] = line.split(/\s+/);
    values[name] = Number(value);
  }
  return values;
}

export class MetricsPanel {
  constructor(root) {
    this.points = kSeries.map(() => []);
    this.last = null;
    this.canvases = kSeries.map((s) => {
      const box = document.createElement('div'); box.className = 'metric';
      const title = document.createElement('div'); title.className = 'metric-title'; title.textContent = s.label;
      const value = document.createElement('span'); value.className = 'metric-value'; title.append(' ', value);
      const canvas = document.createElement('canvas'); canvas.width = 200; canvas.height = 48;
      box.append(title, canvas); root.append(box);
      return {canvas, value};
    });
  }

  add(values, tS) {
    kSeries.forEach((s, i) => {
      if (!(s.name in values)) return;
      let v = values[s.name];
      if (s.rate) {
        if (!this.last || !(s.name in this.last.values)) return;
        v = (v - this.last.values[s.name]) / Math.max(1e-3, tS - this.last.tS);
      }
      v *= s.scale || 1;
      this.points[i].push([tS, v]);
      while (this.points[i].length && this.points[i][0][0] < tS - kKeepS) this.points[i].shift();
    });
    this.last = {values, tS};
    this.draw(tS);
  }

  draw(nowS) {
    this.canvases.forEach(({canvas, value}, i) => {
      const pts = this.points[i];
      const g = canvas.getContext('2d');
      g.clearRect(0, 0, canvas.width, canvas.height);
      if (!pts.length) return;
      const max = Math.max(1e-9, ...pts.map((p) => p[1]));
      g.strokeStyle = '#1060ff'; g.lineWidth = 1.5; g.beginPath();
      pts.forEach(([t, v], k) => {
        const x = canvas.width * (1 - (nowS - t) / kKeepS), y = canvas.height - 2 - (canvas.height - 4) * v / max;
        if (k) g.lineTo(x, y); else g.moveTo(x, y);
      });
      g.stroke();
      const latest = pts[pts.length - 1][1];
      value.textContent = latest >= 100 ? latest.toFixed(0) : latest.toFixed(1);
    });
  }
}
