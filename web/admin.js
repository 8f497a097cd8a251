// The admin page: a thin client of the REST API (docs/web.md "REST"): status, a metrics panel,
// users (add, role, new password, remove), sessions (end), the control queue, instruments, the
// drone's video bit rate, recordings (download, replay in the page), the audit log and the
// configuration. A WebSocket without video carries a replay's frames and events to this page.
import {MetricsPanel, parsePrometheus} from './admin_metrics.js';
import {ReplayView, isReplayFrame} from './replay_view.js';

const $ = (id) => document.getElementById(id);
const state = {me: null, auditOffset: 0, auditTotal: 0};
const kAuditPage = 20;
// Exposed for tests: what the page has done.
window.labodroneAdmin = {refreshes: 0, replay: {}};

async function api(path, options = {}) {
  const res = await fetch(path, options);
  if (res.status === 401) { location.href = '/'; throw new Error('not logged in'); }
  const text = await res.text();
  let body; try { body = JSON.parse(text); } catch { body = text; }
  return {ok: res.ok, status: res.status, body};
}

const sendJson = (path, method, body) =>
  api(path, {method, headers: {'Content-Type': 'application/json'}, body: body === undefined ? undefined : JSON.stringify(body)});
const refusal = (res) => `refused (${res.status}): ${res.body.error}`;

function button(text, onclick) {
  const b = document.createElement('button'); b.textContent = text; b.onclick = onclick; return b;
}

function table(el, header, rows, rowClass) {
  el.innerHTML = '<tr>' + header.map((h) => `<th>${h}</th>`).join('') + '</tr>';
  rows.forEach((r, k) => {
    const tr = document.createElement('tr');
    if (rowClass) tr.className = rowClass(k);
    for (const cell of r) {
      const td = document.createElement('td');
      if (cell instanceof Node) td.append(cell); else td.textContent = cell;
      tr.append(td);
    }
    el.append(tr);
  });
}

function showStatus(s) {
  const rows = [['mission', `${s.mission} ${s.stage || ''}`], ['flying', s.flying ? 'yes' : 'no'],
    ['battery', `${Math.round(s.battery_percent)} %`], ['altitude', `${s.altitude_m.toFixed(2)} m`],
    ['link', `${s.link_state} (${Math.round(100 * s.link_quality)} %)`], ['video', `${s.video_fps.toFixed(1)} frames/s`],
    ['source', s.source],
    ['place', s.unobserved_flight_s > 0
      ? `not confirmed: ${s.unobserved_flight_s.toFixed(1)} s of flight unseen; set the drone on its platform, then press the button below`
      : 'confirmed'],
    ['pose', `x ${s.pose.x.toFixed(2)} y ${s.pose.y.toFixed(2)} z ${s.pose.z.toFixed(2)} m`],
    ['clients', s.clients], ['controller', s.control.controller ? s.control.controller.user : 'nobody']];
  $('status').innerHTML = '';
  for (const [k, v] of rows) {
    const dt = document.createElement('dt'); dt.textContent = k;
    const dd = document.createElement('dd'); dd.textContent = v;
    $('status').append(dt, dd);
  }
}

async function setDown() {
  const res = await sendJson('/api/drone/set-down', 'POST');
  $('set-down-result').textContent = res.ok ? res.body.reason : refusal(res);
  refresh();
}

function userRow(u) {
  const role = document.createElement('select');
  for (const r of ['student', 'teacher', 'admin']) { const o = document.createElement('option'); o.textContent = r; role.append(o); }
  role.value = u.role;
  role.dataset.user = u.name;
  role.onchange = async () => {
    const res = await sendJson('/api/users/' + encodeURIComponent(u.name), 'PUT', {role: role.value});
    $('u-result').textContent = res.ok ? `${u.name} is now ${role.value} (their sessions ended)` : refusal(res);
    refresh();
  };
  const reset = button('new password', async () => {
    const password = prompt(`New password for ${u.name} (8+ characters)`);
    if (!password) return;
    const res = await sendJson('/api/users/' + encodeURIComponent(u.name), 'PUT', {password});
    $('u-result').textContent = res.ok ? `password of ${u.name} changed` : refusal(res);
  });
  const remove = button('remove', async () => {
    if (!confirm(`Remove ${u.name}?`)) return;
    const res = await sendJson('/api/users/' + encodeURIComponent(u.name), 'DELETE');
    $('u-result').textContent = res.ok ? `${u.name} removed` : refusal(res);
    refresh();
  });
  return [u.name, role, reset, remove];
}

async function refreshAudit() {
  const a = await api(`/api/audit?offset=${state.auditOffset}&limit=${kAuditPage}`);
  if (!a.ok) return;
  state.auditTotal = a.body.total;
  const entries = a.body.entries;
  table($('audit'), ['time (UTC)', 'user', 'role', 'action', 'target', 'result', 'detail'],
        entries.map((e) => [e.time.replace('T', ' ').replace('Z', ''), e.user, e.role, e.action, e.target, e.result, e.detail]),
        (k) => entries[k].result === 'refused' ? 'refused' : '');
  $('audit-page').textContent = `${state.auditOffset + 1}–${state.auditOffset + entries.length} of ${state.auditTotal}`;
}

async function refresh() {
  const s = await api('/api/status');
  if (s.ok) showStatus(s.body);
  const u = await api('/api/users');
  if (u.ok) {
    table($('users'), ['name', 'role', '', ''], u.body.users.map(userRow));
    table($('sessions'), ['user', 'role', 'age', 'idle s', ''], u.body.sessions.map((x) => [
      x.user, x.role, `${Math.round(x.age_s / 60)} min`, x.idle_s.toFixed(0),
      x.id === state.me.session ? 'this page' : button('end', async () => { await sendJson('/api/sessions/' + x.id, 'DELETE'); refresh(); }),
    ]));
    const q = u.body.control;
    table($('queue'), ['controller / queued', 'role'],
          [...(q.controller ? [[`${q.controller.user} (controls)`, q.controller.role]] : []), ...q.queue.map((p, k) => [`${k + 1}. ${p.user}`, p.role])]);
  }
  const i = await api('/api/instruments');
  const rows = i.body.lab.map((x) => [x.id, x.name, `${x.width_m} × ${x.height_m}`, 'lab file', 'inspectable', '']);
  for (const x of i.body.uploaded) {
    const where = x.placed ? `[${x.position_m.map((v) => v.toFixed(2)).join(', ')}] m, facing ${x.yaw_deg}°` : 'not placed';
    const place = button('place', async () => {
      const res = await sendJson(`/api/instruments/${x.id}/placement`, 'PUT', placementFromForm());
      $('i-result').textContent = res.ok ? `${x.id} placed: inspectable now` : refusal(res);
      refresh();
    });
    const remove = button('delete', async () => {
      const res = await api('/api/instruments/' + x.id, {method: 'DELETE'});
      if (!res.ok) $('i-result').textContent = refusal(res);
      refresh();
    });
    const actions = document.createElement('span'); if (!x.placed) actions.append(place, ' '); actions.append(remove);
    rows.push([x.id, x.name, `${x.width_m} × ${x.height_m}`, strengthText(x.strength), x.inspectable ? `inspectable at ${where}` : where, actions]);
  }
  table($('instruments'), ['id', 'name', 'size m', 'template strength', 'in the lab', ''], rows);
  const r = await api('/api/recordings');
  $('recordings').innerHTML = '';
  for (const x of r.body.recordings || []) {
    const li = document.createElement('li'); const a = document.createElement('a');
    a.href = x.url; a.textContent = `${x.name} (${(x.bytes / 1e6).toFixed(1)} MB)`;
    li.append(a, ' ', button('replay', () => startReplay(x.name))); $('recordings').append(li);
  }
  await refreshAudit();
  window.labodroneAdmin.refreshes++;
}

const replayView = new ReplayView($('replay'), window.labodroneAdmin.replay);

async function startReplay(name) {
  const res = await sendJson(`/api/recordings/${encodeURIComponent(name)}/replay`, 'POST',
                             {audience: $('replay-audience').value, speed: Number($('replay-speed').value)});
  $('replay-result').textContent = res.ok ? res.body.message : refusal(res);
  refreshAudit();
}

$('replay-stop').onclick = async () => {
  const res = await sendJson('/api/replay', 'DELETE');
  $('replay-result').textContent = res.ok ? res.body.message : refusal(res);
  refreshAudit();
};

// The page's own connection to the lab: no video, only a replay's frames and events.
function connectReplayViewer() {
  const ws = new WebSocket((location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/ws');
  ws.binaryType = 'arraybuffer';
  ws.onopen = () => { ws.send(JSON.stringify({type: 'subscribe', video: 'none'})); window.labodroneAdmin.replay.connected = true; };
  ws.onmessage = (ev) => {
    if (typeof ev.data !== 'string') { if (isReplayFrame(ev.data)) replayView.show(ev.data); return; }
    const msg = JSON.parse(ev.data);
    if (msg.type === 'replay') replayView.onMessage(msg);
  };
  ws.onclose = () => { window.labodroneAdmin.replay.connected = false; setTimeout(connectReplayViewer, 2000); };
}

const metrics = new MetricsPanel($('metrics'));
async function pollMetrics() {
  const res = await fetch('/metrics');
  if (res.ok) metrics.add(parsePrometheus(await res.text()), performance.now() / 1000);
}

$('add-user').onsubmit = async (ev) => {
  ev.preventDefault();
  const res = await sendJson('/api/users', 'POST', {name: $('u-name').value, role: $('u-role').value, password: $('u-password').value});
  $('u-result').textContent = res.ok ? `added ${res.body.added} (${res.body.role}): they may log in now` : refusal(res);
  if (res.ok) { $('u-name').value = ''; $('u-password').value = ''; }
  refresh();
};

// The drone's video (GET /api/video): what the link asks of it, within the drone's range.
async function refreshVideo() {
  const v = await api('/api/video');
  if (!v.ok) { $('video-info').textContent = refusal(v); return; }
  const info = v.body;
  $('video-info').textContent = info.adjustable_bitrate
    ? `${info.drone}: ${info.bitrate_kbps} kbit/s (${info.min_bitrate_kbps}-${info.max_bitrate_kbps}); slow viewers get the shared ${info.low_rendition_kbps} kbit/s rendition`
    : `${info.drone}: its link cannot ask the drone for a bit rate`;
  Object.assign($('v-kbps'), {min: info.min_bitrate_kbps, max: info.max_bitrate_kbps, disabled: !info.adjustable_bitrate});
  $('v-set').disabled = !info.adjustable_bitrate;
  if (!$('v-kbps').value) $('v-kbps').value = info.bitrate_kbps;
}

$('set-bitrate').onsubmit = async (ev) => {
  ev.preventDefault();
  const res = await sendJson('/api/video/bitrate', 'PUT', {kbps: Math.round(+$('v-kbps').value)});
  $('v-result').textContent = res.ok ? `the drone is asked for ${res.body.bitrate_kbps} kbit/s` : refusal(res);
  refreshVideo();
  refreshAudit();
};

$('set-down').onclick = setDown;
$('audit-older').onclick = () => { if (state.auditOffset + kAuditPage < state.auditTotal) { state.auditOffset += kAuditPage; refreshAudit(); } };
$('audit-newer').onclick = () => { state.auditOffset = Math.max(0, state.auditOffset - kAuditPage); refreshAudit(); };

$('save-config').onclick = async () => {
  const res = await api('/api/config', {method: 'PUT', headers: {'Content-Type': 'application/json'}, body: $('config').value});
  if (!res.ok) { $('config-result').textContent = refusal(res); return; }
  const {applied, restart_required: restart} = res.body;
  $('config-result').textContent = 'saved' + (applied.length ? `; applied now: ${applied.join(', ')}` : '') +
    (restart.length ? `; applied at the next start: ${restart.join(', ')}` : '') + (applied.length + restart.length ? '' : ' (nothing changed)');
  refresh();
};

// How well the template can be found and tracked (the server refuses one below its limits).
function strengthText(s) {
  return `SIFT ${s.sift_keypoints} keypoints · ${s.strong_corners} corners · ${Math.round(s.textured_fraction * 100)} % textured`;
}
function placementFromForm() {
  return {position_m: [+$('i-x').value, +$('i-y').value, +$('i-z').value], yaw_deg: +$('i-yaw').value};
}

$('add-instrument').onsubmit = async (ev) => {
  ev.preventDefault();
  const file = $('i-photo').files[0];
  const bytes = new Uint8Array(await file.arrayBuffer());
  let binary = ''; for (const b of bytes) binary += String.fromCharCode(b);
  const body = {
    id: $('i-id').value, name: $('i-name').value, width_m: +$('i-w').value, height_m: +$('i-h').value,
    image_base64: btoa(binary), ...($('i-place').checked ? placementFromForm() : {}),
  };
  const res = await sendJson('/api/instruments', 'POST', body);
  $('i-result').textContent = res.ok
    ? `added ${res.body.id} (${strengthText(res.body.strength)}): ${res.body.inspectable ? 'placed, inspectable now' : 'stored, place it to inspect it'}`
    : refusal(res);
  refresh();
};

state.me = (await api('/api/me')).body;
$('who').textContent = `${state.me.user} · ${state.me.role}`;
const config = await api('/api/config');
$('config').value = config.ok ? JSON.stringify(config.body, null, 2) : `(${config.status}) ${config.body.error}`;
refresh();
refreshVideo();
pollMetrics();
connectReplayViewer();
setInterval(refresh, 3000);
setInterval(pollMetrics, 2000);
