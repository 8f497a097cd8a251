// The front's list of labs (GET /api/labs, server/api/lab_directory.hpp): a link to each lab's page,
// this one marked. "{host}" in a URL is the host this page was loaded from.
const list = document.getElementById('labs');
const error = document.getElementById('labs-error');
try {
  const res = await fetch('/api/labs', {credentials: 'same-origin'});
  if (res.status === 401) location.href = '/';
  const dir = await res.json();
  if (!res.ok) throw new Error(dir.error || res.statusText);
  if (!dir.labs.length) error.textContent = 'this server runs one lab alone: ';
  for (const lab of dir.labs) {
    const li = document.createElement('li');
    const a = document.createElement('a');
    a.href = lab.url.replace('{host}', location.hostname);
    a.textContent = lab.name + (lab.id === dir.self ? ' (this server)' : '');
    li.append(a, lab.janus ? ' · video through Janus' : '');
    list.append(li);
  }
  if (!dir.labs.length) {
    const a = document.createElement('a');
    a.href = '/lab.html';
    a.textContent = 'the lab';
    error.append(a);
  }
} catch (e) {
  error.textContent = 'cannot read the lab directory: ' + e.message;
}
