// End-to-end in a real browser (headless Debian chromium driven by playwright-core): what each role
// may do on the lab and admin pages. A spectator has stop but no motor cut (the space bar stops);
// the student holding control, a teacher and an admin may cut the motors.
// Usage: node roles_flow.mjs BASE_URL OUT_DIR
import {chromium} from 'playwright-core';

const [base, out] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});

async function login(user) {
  const context = await browser.newContext({viewport: {width: 1480, height: 900}});
  const page = await context.newPage();
  page.on('pageerror', (e) => fail(`${user}: page error: ${e.message}`));
  await page.goto(base + '/');
  await page.fill('#user', user);
  await page.fill('#password', user + '-pass');
  await page.click('#login-button');
  await page.waitForURL('**/lab.html');
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

try {
  await spectatorStopsButCannotCut();
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
if (!process.exitCode) console.log('1 passed, 0 failed');
