// End-to-end in a real browser (headless Debian chromium driven by playwright-core) against
// `labodrone serve` on the simulated lab: an admin replays a flight recording in the page. To the
// admin's own pages: the admin page's replay view shows the recorded frames, a student's lab page gets
// none. Stopped from the page. Then to everyone: the student's lab page shows the replay beside its
// live video, which keeps playing. The audit log names the replay's start and stop.
// Usage: node replay_flow.mjs BASE_URL OUT_DIR
import {launchChromium, logIn} from './browser.mjs';

const [base, out] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await launchChromium();
const onPageError = (who) => (e) => fail(`${who}: page error: ${e.message}`);

const admin = (await logIn(browser, base, 'admin', 'admin-pass', {landing: /admin\.html$/, onPageError: onPageError('admin')})).page;
const student = (await logIn(browser, base, 'student1', 'student1-pass', {onPageError: onPageError('student1')})).page;
await student.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});
await admin.waitForFunction(() => window.labodroneAdmin.replay.connected, null, {timeout: 10000});
const replayButton = '#recordings li:has-text("flight.ldrec") button';
await admin.waitForSelector(replayButton, {timeout: 10000});

// To the admin's pages only, at half speed (the recording is a few seconds long).
await admin.selectOption('#replay-audience', 'me');
await admin.selectOption('#replay-speed', '0.5');
await admin.click(replayButton);
await admin.waitForFunction(() => window.labodroneAdmin.replay.replayFrames >= 10, null, {timeout: 20000});
if (!(await admin.isVisible('#replay canvas'))) fail('the admin page does not show the replay');
const caption = await admin.textContent('#replay .replay-caption');
if (!caption.includes('flight.ldrec') || !caption.includes('playing')) fail(`the replay's caption: '${caption}'`);
await admin.screenshot({path: out + '/replay_admin.png', fullPage: true});
const studentSaw = await student.evaluate(() => window.labodrone.replayFrames);
if (studentSaw !== 0) fail(`a student's page got ${studentSaw} frames of a replay meant for the admin`);
if (await student.isVisible('#replay')) fail('a student\'s page shows a replay meant for the admin');
await admin.click('#replay-stop');
await admin.waitForFunction(() => window.labodroneAdmin.replay.replayState === 'stopped', null, {timeout: 10000});
if (!(await admin.textContent('#replay-result')).includes('stopped')) fail('the stop is not confirmed on the page');
console.log(`to the admin: ${await admin.evaluate(() => window.labodroneAdmin.replay.replayFrames)} frames shown, ` +
            `the student's page 0; stopped at ${await admin.evaluate(() => window.labodroneAdmin.replay.replayPositionS.toFixed(1))} s`);

// To everyone: the student's page shows it beside the live video.
await admin.selectOption('#replay-audience', 'everyone');
await admin.selectOption('#replay-speed', '1');
const liveBefore = await student.evaluate(() => window.labodrone.framesDecoded);
await admin.click(replayButton);
await student.waitForFunction(() => window.labodrone.replayFrames >= 10, null, {timeout: 20000});
await student.waitForSelector('#replay', {state: 'visible'});
await student.waitForFunction((n) => window.labodrone.framesDecoded > n + 10, liveBefore, {timeout: 10000});
await student.screenshot({path: out + '/replay_student.png', fullPage: true});
await student.waitForFunction(() => ['ended', 'stopped'].includes(window.labodrone.replayState) ||
                                    document.querySelector('#replay .replay-caption').textContent.includes('ended'),
                              null, {timeout: 30000}).catch(() => fail('the replay to everyone never ended'));
console.log(`to everyone: the student's page showed ${await student.evaluate(() => window.labodrone.replayFrames)} ` +
            `replay frames while its live video went on (${await student.evaluate(() => window.labodrone.framesDecoded) - liveBefore} frames)`);

await admin.waitForFunction(() => document.getElementById('audit').textContent.includes('replay_start') &&
                                  document.getElementById('audit').textContent.includes('replay_stop'), null, {timeout: 10000})
  .catch(() => fail('the audit log does not name the replay'));
await browser.close();
if (!process.exitCode) console.log('PASS replay_flow');
