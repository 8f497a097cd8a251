// The admin page: a thin client of the REST API (GET /api/status, /api/users, /api/instruments,
// /api/recordings, GET/PUT /api/config, POST/DELETE /api/instruments).
const $ = (id) => document.getElementById(id);

async function api(path, options = {}) {
  const res = await fetch(path, options);
  if (res.status === 401) { location.href = '/'; throw new Error('not logged in'); }
  const text = await res.text();
  let body; try { body = JSON.parse(text); } catch { body = text; }
  return {ok: res.ok, status: res.status, body};
}

function table(el, header, rows) {
  el.innerHTML = '<tr>' + header.map((h) => `<th>${h}</th>`).join('') + '</tr>';
  for (const r of rows) {
    const tr = document.createElement('tr');
    for (const cell of r) { const td = document.createElement('td'); if (cell instanceof Node) td.append(cell); else td.textContent = cell; tr.append(td); }
    el.append(tr);
  }
}

async function refresh() {
  const s = await api('/api/status');
  $('status').textContent = JSON.stringify(s.body, null, 2);
  const u = await api('/api/users');
  if (u.ok) {
    table($('sessions'), ['user', 'role', 'idle s'], u.body.sessions.map((x) => [x.user, x.role, x.idle_s.toFixed(0)]));
    $('queue').textContent = JSON.stringify(u.body.control, null, 2);
  }
  const i = await api('/api/instruments');
  const rows = i.body.lab.map((x) => [x.id, x.name, `${x.width_m} × ${x.height_m}`, 'lab']);
  for (const x of i.body.uploaded) {
    const del = document.createElement('button'); del.textContent = 'delete';
    del.onclick = async () => { await api('/api/instruments/' + x.id, {method: 'DELETE'}); refresh(); };
    rows.push([x.id, x.name, `${x.width_m} × ${x.height_m}`, del]);
  }
  table($('instruments'), ['id', 'name', 'size m', ''], rows);
  const r = await api('/api/recordings');
  $('recordings').innerHTML = '';
  for (const x of r.body.recordings || []) {
    const li = document.createElement('li'); const a = document.createElement('a');
    a.href = x.url; a.textContent = `${x.name} (${(x.bytes / 1e6).toFixed(1)} MB)`; li.append(a); $('recordings').append(li);
  }
}

$('save-config').onclick = async () => {
  const res = await api('/api/config', {method: 'PUT', headers: {'Content-Type': 'application/json'}, body: $('config').value});
  $('config-result').textContent = res.ok ? 'saved: restart the server to apply it' : `refused (${res.status}): ${res.body.error}`;
};

$('add-instrument').onsubmit = async (ev) => {
  ev.preventDefault();
  const file = $('i-photo').files[0];
  const bytes = new Uint8Array(await file.arrayBuffer());
  let binary = ''; for (const b of bytes) binary += String.fromCharCode(b);
  const body = {
    id: $('i-id').value, name: $('i-name').value, width_m: +$('i-w').value, height_m: +$('i-h').value,
    position_m: [+$('i-x').value, +$('i-y').value, +$('i-z').value], yaw_deg: +$('i-yaw').value, image_base64: btoa(binary),
  };
  const res = await api('/api/instruments', {method: 'POST', headers: {'Content-Type': 'application/json'}, body: JSON.stringify(body)});
  $('i-result').textContent = res.ok ? `added (${res.body.texture_corners} corners)` : `refused (${res.status}): ${res.body.error}`;
  refresh();
};

const me = await api('/api/me');
$('who').textContent = `${me.body.user} · ${me.body.role}`;
const config = await api('/api/config');
$('config').value = config.ok ? JSON.stringify(config.body, null, 2) : `(${config.status}) ${config.body.error}`;
refresh();
setInterval(refresh, 3000);
