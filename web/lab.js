// The lab page: live video (video_view.js) with the measured glass-to-browser latency, mission
// commands, the control queue, events, telemetry plots and the map. One WebSocket (/ws) carries JSON
// events (text) and video (binary: H.264 access units or JPEG frames; docs/web.md).
import {MapView} from './map_view.js';
import {StageTimelineView} from './stage_timeline.js';
import {formatDuration, TeacherPanel} from './teacher_panel.js';
import {TelemetryView} from './telemetry_view.js';
import {VideoView} from './video_view.js';

const $ = (id) => document.getElementById(id);
const view = new TelemetryView(document);
const map = new MapView($('map'));
const timeline = new StageTimelineView($('timeline'), $('timeline-title'));
const state = {ws: null, role: null, controlling: false, nextId: 1, lastFpsT: performance.now(), heartbeat: null, controlSeq: -1};
let teacher = null;  // the teacher's panel (teacher_panel.js), for teachers and admins
// Exposed for tests and curious users: what the page has seen.
window.labodrone = {stages: [], acks: [], connected: false, timeline: null, slamMap: null, lab: null, send: (obj) => send(obj)};

function logEvent(text, cls) {
  const li = document.createElement('li');
  li.textContent = new Date().toLocaleTimeString() + ' ' + text;
  if (cls) li.className = cls;
  $('events').prepend(li);
  while ($('events').children.length > 100) $('events').lastChild.remove();
}

function send(obj) {
  if (state.ws && state.ws.readyState === WebSocket.OPEN) state.ws.send(JSON.stringify(obj));
}

function command(name, extra = {}) {
  send({type: 'command', id: state.nextId++, command: name, ...extra});
}

const video = new VideoView(document, send, window.labodrone);

// Cutting the motors drops the drone: the server allows it to the controller, teachers and admins
// only, and the page offers it to them only. Everyone has stop (hover, then land).
function mayCutMotors() { return state.controlling || state.role === 'teacher' || state.role === 'admin'; }
function showStopButtons() {
  $('emergency').hidden = !mayCutMotors();
  $('stop-hint').hidden = mayCutMotors();
}

function onControl(msg) {
  // States are sent after the server's lock is released and may arrive out of order: keep the newest.
  if (msg.seq <= state.controlSeq) return;
  state.controlSeq = msg.seq;
  state.controlling = !!(msg.you && msg.you.controlling);
  showStopButtons();
  const c = msg.controller;
  $('control-state').textContent = c
    ? `${c.user} (${c.role}) has control for ${formatDuration(msg.held_s)}` + (msg.remaining_s >= 0 ? `, ${formatDuration(msg.remaining_s)} left` : '')
    : 'nobody controls the drone';
  $('turn').textContent = msg.you && msg.you.controlling
    ? (msg.remaining_s >= 0 ? `your turn: ${Math.round(msg.remaining_s)} s left` : 'you have control (no time limit)')
    : (msg.you && msg.you.position ? `you are number ${msg.you.position} in the queue` : 'you are watching');
  const q = $('queue');
  q.innerHTML = '';
  for (const p of msg.queue) { const li = document.createElement('li'); li.textContent = `${p.user} (${p.role}), waiting ${formatDuration(p.waited_s)}`; q.append(li); }
  if (teacher) teacher.onControl(msg);
}

function onMessage(msg) {
  switch (msg.type) {
    case 'hello': {
      state.role = msg.role;
      $('who').textContent = `${msg.user} · ${msg.role}`;
      for (const el of document.querySelectorAll('.teacher-only')) el.hidden = msg.role === 'student';
      $('admin-link').hidden = msg.role !== 'admin';
      if (msg.role !== 'student' && !teacher) teacher = new TeacherPanel({send, command, logEvent});
      showStopButtons();
      const sel = $('instrument'); sel.innerHTML = '';
      for (const i of msg.instruments) { const o = document.createElement('option'); o.value = i.id; o.textContent = i.name || i.id; sel.append(o); }
      map.setLab(msg.lab, msg.instruments);
      window.labodrone.lab = msg.lab;
      video.start();
      break;
    }
    case 'overlay': video.onGeometry(msg); break;
    case 'subscribed': break;
    case 'replay': video.replay.onMessage(msg); break;
    case 'rendition': video.onRendition(msg); break;
    case 'slam_map':
      map.setSlamMap(msg);
      window.labodrone.slamMap = {revision: msg.revision, points: msg.points.length};
      break;
    case 'telemetry':
      view.add(msg);
      timeline.render(msg.timeline, msg.t);
      window.labodrone.timeline = msg.timeline;
      $('mission').textContent = msg.mission;
      $('stage').textContent = msg.stage || '–';
      $('source').textContent = msg.source;
      $('source').style.background = msg.source_colour;
      $('link-state').textContent = msg.link_state;
      $('battery').textContent = `${Math.round(msg.battery_percent)} %`;
      $('battery').className = msg.battery_percent < 20 ? 'low' : '';
      $('altitude').textContent = `${msg.altitude_m.toFixed(2)} m`;
      $('slam-state').textContent = msg.slam_state;
      // After flight the navdata did not see, a landed drone takes no mission until an admin sets it down.
      $('place-unconfirmed').hidden = !(msg.unobserved_flight_s > 0 && !msg.flying);
      break;
    case 'control': onControl(msg); break;
    case 'ack':
      window.labodrone.acks.push(msg);
      logEvent(`${msg.command}: ${msg.accepted ? 'accepted' : 'rejected'}${msg.reason ? ' — ' + msg.reason : ''}`, msg.accepted ? '' : 'rejected');
      break;
    case 'event':
      if (msg.kind === 'stage') window.labodrone.stages.push(msg.stage);
      logEvent(msg.message || `${msg.kind} ${msg.mission} ${msg.stage}`, ['error', 'emergency', 'stop'].includes(msg.kind) ? 'rejected' : '');
      break;
    case 'notice':
      if (msg.kind === 'granted') logEvent('you have control' + (msg.remaining_s > 0 ? ` for ${Math.round(msg.remaining_s)} s` : ''));
      if (msg.kind === 'warning') logEvent(`your turn ends in ${Math.round(msg.remaining_s)} s`, 'rejected');
      if (msg.kind === 'ended') logEvent(msg.by ? `your turn was ended by ${msg.by}: ${msg.reason}` : `your turn ended: ${msg.reason}`, 'rejected');
      break;
    case 'error': logEvent(`error ${msg.status}: ${msg.error}`, 'rejected'); break;
  }
}

function connect() {
  const ws = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws');
  ws.binaryType = 'arraybuffer';
  state.ws = ws;
  ws.onopen = () => {
    state.controlSeq = -1;
    $('connection').textContent = 'connected'; $('connection').className = 'badge ok';
    window.labodrone.connected = true;
    state.heartbeat = setInterval(() => send({type: 'heartbeat'}), 2000);
  };
  ws.onmessage = (ev) => { if (typeof ev.data === 'string') onMessage(JSON.parse(ev.data)); else video.onBinary(ev.data); };
  ws.onclose = () => {
    window.labodrone.connected = false;
    clearInterval(state.heartbeat);
    $('connection').textContent = 'disconnected — retrying'; $('connection').className = 'badge';
    setTimeout(async () => {
      const me = await fetch('/api/me');
      if (me.status === 401) location.href = '/'; else connect();
    }, 1000);
  };
}

for (const b of document.querySelectorAll('[data-command]')) b.addEventListener('click', () => command(b.dataset.command));
$('inspect').addEventListener('click', () => command('inspect', {instrument: $('instrument').value, hold_s: Number($('hold-s').value)}));
// A jog is one small step (0.2 m or 15°); the server bounds it, the flight software refuses it during
// a mission or outside the geofence, and the refusal is shown in the events.
for (const b of document.querySelectorAll('[data-jog]')) {
  const [axis, step] = b.dataset.jog.split(':');
  b.addEventListener('click', () => command('jog', {[axis]: Number(step)}));
}
$('emergency').addEventListener('click', () => command('emergency_stop'));
$('stop').addEventListener('click', () => command('stop'));
$('request-control').addEventListener('click', () => send({type: 'request_control'}));
$('release-control').addEventListener('click', () => send({type: 'release_control'}));
$('take-over').addEventListener('click', () => send({type: 'take_over'}));
$('logout').addEventListener('click', async () => { await fetch('/api/logout', {method: 'POST'}); location.href = '/'; });
document.addEventListener('keydown', (e) => {
  if (e.key !== ' ' || e.target !== document.body) return;
  e.preventDefault();
  command(mayCutMotors() ? 'emergency_stop' : 'stop');
});

setInterval(() => {
  const now = performance.now();
  $('fps').textContent = (video.takeFrameCount() * 1000 / (now - state.lastFpsT)).toFixed(1);
  state.lastFpsT = now;
}, 1000);
(function redraw() { view.draw(); map.draw(view.last); requestAnimationFrame(redraw); })();

fetch('/api/me').then((r) => { if (r.status === 401) location.href = '/'; else connect(); });
