// The teacher's part of the lab page (teachers and admins): faces registered from photos (POST
// /api/people as multipart/form-data), the person face-follow follows (PUT /api/face_follow), face-follow
// started and stopped with a take-over of control, and a student's turn ended with a reason
// (POST /api/control/end_turn). docs/web.md "The teacher's routes".

const $ = (id) => document.getElementById(id);

export function formatDuration(seconds) {
  const s = Math.max(0, Math.round(seconds));
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}`;
}

async function answerOf(response) {
  const body = await response.json().catch(() => ({}));
  return {ok: response.ok, status: response.status, body, error: body.error || `HTTP ${response.status}`};
}

export class TeacherPanel {
  // `lab`: {send(obj), command(name, extra), logEvent(text, cls)} from the lab page.
  constructor(lab) {
    this.lab = lab;
    this.controlling = false;
    this.controller = null;  // {user, role} holding control
    this.followed = null;    // the server's choice
    $('teacher-panel').hidden = false;
    $('register-form').addEventListener('submit', (e) => { e.preventDefault(); this.register(); });
    $('start-follow').addEventListener('click', () => this.startFollow());
    $('stop-follow').addEventListener('click', () => this.withControl(() => this.lab.command('stop_face_follow')));
    $('end-turn').addEventListener('click', () => this.endTurn());
    $('people').addEventListener('click', (e) => {
      const name = e.target.dataset.person;
      if (!name) return;
      if (e.target.dataset.action === 'follow') { $('follow-person').value = name; this.choose(name); }
      if (e.target.dataset.action === 'delete') this.remove(name);
    });
    this.refresh();
  }

  onControl(msg) {
    this.controlling = !!(msg.you && msg.you.controlling);
    this.controller = msg.controller;
    const student = msg.controller && msg.controller.role === 'student';
    $('end-turn').disabled = !student;
    $('end-turn-who').textContent = student ? `${msg.controller.user}'s turn` : 'no student holds control';
  }

  async refresh() {
    const r = await answerOf(await fetch('/api/people'));
    if (!r.ok) { $('people-note').textContent = `registered people: ${r.error}`; return; }
    this.followed = r.body.followed;
    this.maxUploadBytes = r.body.max_upload_bytes;
    const size = r.body.photo_size;
    $('people-note').textContent = `Photos: PNG or JPEG, ${size.width}x${size.height} (the drone's front camera), the face alone and frontal.`;
    const select = $('follow-person');
    select.innerHTML = '<option value="">(nobody chosen)</option>';
    const rows = $('people');
    rows.innerHTML = '';
    for (const p of r.body.people) {
      const option = document.createElement('option');
      option.value = p.name; option.textContent = p.name;
      select.append(option);
      const tr = document.createElement('tr');
      const reg = p.registration;
      const cells = p.error ? [p.name, `unreadable: ${p.error}`, '', '']
        : [p.name, `${p.fit_rms_px.toFixed(2)} px`, reg && reg.head_turn_views ? `${reg.head_turn_views} views` : 'none',
           reg ? `${reg.by}, ${new Date(reg.unix_s * 1000).toLocaleString()}` : 'command line'];
      for (const text of cells) { const td = document.createElement('td'); td.textContent = text; tr.append(td); }
      const td = document.createElement('td');
      for (const [action, label] of [['follow', 'Follow'], ['delete', 'Delete']]) {
        const b = document.createElement('button');
        b.textContent = label; b.dataset.person = p.name; b.dataset.action = action;
        td.append(b);
      }
      tr.append(td);
      if (p.name === this.followed) tr.className = 'followed';
      rows.append(tr);
    }
    select.value = this.followed || '';
    $('follow-note').textContent = this.followed ? `face-follow follows ${this.followed}` : 'face-follow follows the face the drone followed last (face.teacher at start)';
  }

  async register() {
    // The whole form must fit the server's body limit (413 otherwise): said here before the upload.
    const files = [...$('frontal-photos').files, ...$('turn-photos').files];
    const bytes = files.reduce((sum, f) => sum + f.size, 0);
    if (this.maxUploadBytes && bytes > this.maxUploadBytes) {
      const mb = (n) => (n / 1048576).toFixed(1);
      $('register-result').textContent = `refused: the photos are ${mb(bytes)} MB, the server takes at most ${mb(this.maxUploadBytes)} MB ` +
        '(send JPEG, or fewer head-turn frames)';
      $('register-result').className = 'rejected';
      return;
    }
    const data = new FormData();
    data.append('name', $('person-name').value.trim());
    for (const f of $('frontal-photos').files) data.append('frontal', f, f.name);
    for (const f of $('turn-photos').files) data.append('turn', f, f.name);
    if ($('ipd-mm').value) data.append('ipd_mm', $('ipd-mm').value);
    if ($('replace-person').checked) data.append('replace', 'true');
    $('register-result').textContent = 'registering… (the face fit takes a few seconds)';
    $('register-person').disabled = true;
    try {
      const r = await answerOf(await fetch('/api/people', {method: 'POST', body: data}));
      const turn = r.body.head_turn;
      $('register-result').textContent = r.ok
        ? `registered ${r.body.name}: fit RMS ${r.body.fit_rms_px.toFixed(2)} px` +
          (turn ? `, head turn ${turn.views} views (${turn.rms_before_px.toFixed(2)} → ${turn.rms_after_px.toFixed(2)} px)` : '')
        : `refused (${r.status}): ${r.error}`;
      $('register-result').className = r.ok ? 'ok' : 'rejected';
      if (r.ok) await this.refresh();
    } finally {
      $('register-person').disabled = false;
    }
  }

  async choose(name) {
    const r = await answerOf(await fetch('/api/face_follow', {method: 'PUT', headers: {'Content-Type': 'application/json'},
                                                             body: JSON.stringify({person: name || null})}));
    if (!r.ok) { this.lab.logEvent(`follow ${name}: ${r.error}`, 'rejected'); return false; }
    await this.refresh();
    return true;
  }

  async remove(name) {
    const r = await answerOf(await fetch(`/api/people/${encodeURIComponent(name)}`, {method: 'DELETE'}));
    if (!r.ok) this.lab.logEvent(`delete ${name}: ${r.error}`, 'rejected');
    await this.refresh();
  }

  // Face-follow is a teacher's action: control is taken over first when someone else holds it.
  withControl(action) {
    if (!this.controlling) this.lab.send({type: 'take_over'});
    action();
  }

  async startFollow() {
    const name = $('follow-person').value;
    if ((name || null) !== this.followed && !(await this.choose(name))) return;
    this.withControl(() => this.lab.command('find_teacher'));
  }

  async endTurn() {
    if (!this.controller) return;
    const user = this.controller.user;
    const reason = $('end-turn-reason').value.trim();
    const r = await answerOf(await fetch('/api/control/end_turn', {method: 'POST', headers: {'Content-Type': 'application/json'},
                                                                   body: JSON.stringify({user, reason})}));
    this.lab.logEvent(r.ok ? `ended ${user}'s turn: ${reason}` : `end turn: ${r.error}`, r.ok ? '' : 'rejected');
    if (r.ok) $('end-turn-reason').value = '';
  }
}
