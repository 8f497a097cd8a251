// End-to-end in a real browser (headless Debian chromium driven by playwright-core): what each role
// may do on the lab and admin pages. A spectator has stop but no motor cut (the space bar stops);
// the student holding control, a teacher and an admin may cut the motors. The admin page: status,
// live metrics, the drone's bit rate set (and refused out of range), a user added there who then logs
// in, the audit log naming both, the user removed.
// Usage: node roles_flow.mjs BASE_URL OUT_DIR
import {launchChromium, logIn} from './browser.mjs';

const [base, out] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await launchChromium();

async function login(user, password = user + '-pass') {
  const {page} = await logIn(browser, base, user, password, {
    onPageError: (e) => fail(`${user}: page error: ${e.message}`),
    prepare: (p) => {
      p.sent = [];  // the JSON this page sent on its WebSocket
      p.on('websocket', (ws) => ws.on('framesent', (f) => { if (typeof f.payload === 'string') p.sent.push(f.payload); }));
    },
    landing: /\/(lab|admin)\.html$/,  // admins land on their own page
  });
  if (page.url().endsWith('admin.html')) return page;
  await page.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});
  await page.waitForFunction(() => document.getElementById('who').textContent.includes('·'));
  return page;
}

const eventsText = (page) => page.textContent('#events');

async function spectatorStopsButCannotCut() {
  const spectator = await login('student2');
  if (await spectator.isVisible('#emergency')) fail('a spectator is offered the motor cut');
  if (!(await spectator.isVisible('#stop'))) fail('a spectator has no stop button');
  await spectator.keyboard.press('Space');
  await spectator.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'stop'));
  await spectator.waitForFunction(() => document.getElementById('events').textContent.includes('stop by student2'));
  // A motor cut forged past the page is refused by the server with 403.
  await spectator.evaluate(() => window.labodrone.send({type: 'command', id: 900, command: 'emergency_stop'}));
  await spectator.waitForFunction(() => document.getElementById('events').textContent.includes('error 403'));
  const controller = await login('student1');
  await controller.click('#request-control');
  await controller.waitForFunction(() => document.getElementById('turn').textContent.includes('your turn'));
  await controller.waitForSelector('#emergency', {state: 'visible'});
  const teacher = await login('teacher');
  await teacher.waitForSelector('#emergency', {state: 'visible'});
  await teacher.click('#emergency');
  await teacher.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'emergency_stop' && a.accepted));
  await spectator.waitForFunction(() => document.getElementById('events').textContent.includes('emergency stop by teacher'));
  await spectator.screenshot({path: out + '/roles_spectator.png', fullPage: true});
  console.log('spectator: stop by space bar, motor cut refused (403); teacher: motor cut; events: ' +
              (await eventsText(spectator)).length + ' characters');
  for (const p of [spectator, controller, teacher]) await p.context().close();
}

async function adminAddsUserWhoLogsIn() {
  const admin = await login('admin');
  admin.on('dialog', (d) => d.accept());
  await admin.waitForFunction(() => window.labodroneAdmin && window.labodroneAdmin.refreshes >= 1);
  const status = await admin.textContent('#status');
  if (!status.includes('battery')) fail('the status panel shows no battery: ' + status);
  if (!status.includes('placeconfirmed')) fail('the status panel does not say the place is confirmed: ' + status);
  // The drone set on its platform: the flight software's answer shown, the action audited.
  await admin.click('#set-down');
  await admin.waitForFunction(() => document.getElementById('set-down-result').textContent.includes('its place is the base'));
  await admin.waitForFunction(() => document.getElementById('audit').textContent.includes('drone_set_down'), null, {timeout: 10000});
  // Two polls of /metrics make the first rates.
  await admin.waitForFunction(() => [...document.querySelectorAll('.metric-value')].filter((v) => v.textContent).length >= 5,
                              null, {timeout: 10000});
  await admin.fill('#u-name', 'dana');
  await admin.selectOption('#u-role', 'student');
  await admin.fill('#u-password', 'dana-pass-1');
  await admin.click('#u-add');
  await admin.waitForFunction(() => document.getElementById('u-result').textContent.includes('added dana'));
  // Refused with its reason: a second dana.
  await admin.fill('#u-name', 'dana');
  await admin.fill('#u-password', 'dana-pass-2');
  await admin.click('#u-add');
  await admin.waitForFunction(() => document.getElementById('u-result').textContent.includes('409'));
  const dana = await login('dana', 'dana-pass-1');
  const who = await dana.textContent('#who');
  if (!who.includes('dana · student')) fail('the new user is not logged in as a student: ' + who);
  await admin.waitForFunction(() => document.getElementById('audit').textContent.includes('user_add'), null, {timeout: 10000});
  await admin.waitForFunction(() => document.getElementById('sessions').textContent.includes('dana'), null, {timeout: 10000});
  // The drone's bit rate: shown with its range, set, refused out of range with the server's reason, audited.
  await admin.waitForFunction(() => document.getElementById('video-info').textContent.includes('4000 kbit/s (250-4000)'));
  await admin.fill('#v-kbps', '1500');
  await admin.click('#v-set');
  await admin.waitForFunction(() => document.getElementById('v-result').textContent.includes('asked for 1500 kbit/s'));
  await admin.waitForFunction(() => document.getElementById('video-info').textContent.includes(': 1500 kbit/s'));
  await admin.fill('#v-kbps', '100');
  await admin.click('#v-set');
  await admin.waitForFunction(() => document.getElementById('v-result').textContent.includes('refused (400)'));
  const refused = await admin.textContent('#v-result');
  if (!refused.includes('must be in [250, 4000]')) fail('the refused bit rate does not say the range: ' + refused);
  await admin.waitForFunction(() => document.getElementById('audit').textContent.includes('video_bitrate'), null, {timeout: 10000});
  await admin.screenshot({path: out + '/roles_admin.png', fullPage: true});
  // Removed: dana's page goes back to the login page.
  const row = admin.locator('#users tr', {hasText: 'dana'});
  await row.locator('button', {hasText: 'remove'}).click();
  await admin.waitForFunction(() => document.getElementById('u-result').textContent.includes('dana removed'));
  await dana.waitForURL((u) => !u.pathname.endsWith('lab.html'), {timeout: 10000});
  console.log('admin: status and metrics shown; the drone set down; the bit rate set and refused out of range; dana added, logged in, seen in sessions and the audit log, removed');
  for (const p of [admin, dana]) await p.context().close();
}

async function studentJogsAndSetsHoldTime() {
  const student = await login('student3');
  await student.click('#request-control');
  await student.waitForFunction(() => document.getElementById('turn').textContent.includes('your turn'));
  await student.click('button[data-jog="dz_m:0.2"]');
  await student.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'jog'));
  await student.fill('#hold-s', '25');
  await student.click('#inspect');
  await student.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'inspect'));
  const acks = await student.evaluate(() => window.labodrone.acks.map((a) => `${a.command} ${a.accepted} ${a.reason}`));
  const sent = student.sent.map((t) => JSON.parse(t));
  if (!sent.some((m) => m.command === 'jog' && m.dz_m === 0.2)) fail('no jog up was sent');
  if (!sent.some((m) => m.command === 'inspect' && m.hold_s === 25)) fail('the hold time was not sent with inspect');
  if (!acks.some((a) => a.startsWith('jog true'))) fail('the jog was not accepted: ' + acks.join('; '));
  console.log('student: ' + acks.join('; '));
  await student.click('#release-control');
  await student.context().close();
}

try {
  await studentJogsAndSetsHoldTime();
  await spectatorStopsButCannotCut();
  await adminAddsUserWhoLogsIn();
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
if (!process.exitCode) console.log('1 passed, 0 failed');
