// End-to-end in a real browser: headless Debian chromium driven by playwright-core. A student logs
// in, takes control, starts an inspection, sees video frames arrive and the stages advance in the
// mission's timeline, sees the map with the room outline (and, over the test doubles, the SLAM map's
// points drawn), presses the emergency stop and sees it accepted and ending the timeline; the page
// is saved as a screenshot.
// Usage: node student_flow.mjs BASE_URL SCREENSHOT.png [scripted|sim]
import {launchChromium} from './browser.mjs';

// The test checks that video flows; the frame-rate target (>= 25 frames/s) is checked by the
// benchmark run of the same script with MIN_FPS=25 (docs/web.md), on a machine doing nothing else.
const minFps = Number(process.env.MIN_FPS || 5);

const [base, screenshot, mode = 'scripted'] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await launchChromium();
try {
  const page = await browser.newPage({viewport: {width: 1480, height: 900}});
  page.on('pageerror', (e) => fail('page error: ' + e.message));
  await page.goto(base + '/');
  // A wrong password first: the page must say so.
  await page.fill('#user', 'student1');
  await page.fill('#password', 'wrong');
  await page.click('#login-button');
  await page.waitForFunction(() => document.getElementById('login-error').textContent.includes('wrong password'));
  await page.fill('#password', 'student1-pass');
  await page.click('#login-button');
  await page.waitForURL('**/lab.html');
  await page.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});

  // Video arrives, with a measured latency.
  await page.waitForFunction(() => window.labodrone.framesDecoded >= 30, null, {timeout: 15000});
  const t0 = await page.evaluate(() => ({n: window.labodrone.framesDecoded, t: performance.now()}));
  await page.waitForTimeout(2000);
  const t1 = await page.evaluate(() => ({n: window.labodrone.framesDecoded, t: performance.now(), lat: window.labodrone.latencyMedianMs}));
  const fps = (t1.n - t0.n) * 1000 / (t1.t - t0.t);
  console.log(`frames/s in the browser: ${fps.toFixed(1)}; median glass-to-browser latency: ${t1.lat.toFixed(0)} ms`);
  if (fps < minFps) fail(`only ${fps.toFixed(1)} frames/s reached the page`);

  // Without control, a command is refused with the reason.
  await page.click('#inspect');
  await page.waitForFunction(() => window.labodrone.acks.some((a) => !a.accepted && a.reason.includes('control')));
  // Take control and inspect; the stages must advance.
  await page.click('#request-control');
  await page.waitForFunction(() => document.getElementById('turn').textContent.includes('your turn'));
  await page.selectOption('#instrument', 'oscilloscope');
  await page.click('#inspect');
  await page.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'inspect' && a.accepted));
  await page.waitForFunction(() => new Set(window.labodrone.stages.filter((s) => s)).size >= 3, null, {timeout: 20000});
  const stages = await page.evaluate(() => [...new Set(window.labodrone.stages)]);
  console.log('stages seen: ' + stages.join(' → '));
  const shown = await page.textContent('#stage');
  if (!shown || shown === '–') fail('the stage is not shown');
  // The timeline lists the stages begun so far, the current one last, and those still to come.
  await page.waitForFunction(() => document.querySelectorAll('#timeline li.stage-done').length >= 2, null, {timeout: 20000});
  const rows = await page.$$eval('#timeline li', (lis) => lis.map((li) => li.className + ': ' + li.textContent));
  console.log('timeline: ' + rows.join(' | '));
  if (!rows.some((r) => r.startsWith('stage-current'))) fail('the timeline shows no current stage');
  if (!(await page.textContent('#timeline-title')).includes('inspect')) fail('the timeline names no mission');

  // The map: the room outline from hello; the SLAM map's points drawn in their grey. The simulated
  // lab's SLAM may not have a map yet this early: its points are counted, not required.
  if (!(await page.evaluate(() => window.labodrone.lab && window.labodrone.lab.room))) fail('hello gave no room outline');
  if (mode === 'scripted') await page.waitForFunction(() => window.labodrone.slamMap && window.labodrone.slamMap.points > 0, null, {timeout: 5000});
  const drawn = await page.evaluate(() => {
    const c = document.getElementById('map');
    const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let grey = 0;
    for (let i = 0; i < px.length; i += 4) grey += px[i] === 0x6a && px[i + 1] === 0x6a && px[i + 2] === 0x6a && px[i + 3] === 255;
    return {grey, points: window.labodrone.slamMap ? window.labodrone.slamMap.points : 0};
  });
  console.log(`SLAM map: ${drawn.points} points, ${drawn.grey} map pixels in their colour`);
  if (drawn.points > 0 && drawn.grey === 0) fail('SLAM map points were received but not drawn on the map');

  await page.click('#emergency');
  await page.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'emergency_stop' && a.accepted));
  await page.waitForFunction(() => document.getElementById('mission').textContent === 'emergency');
  await page.waitForFunction(() => document.querySelector('#timeline .stage-result.failed'), null, {timeout: 5000});
  await page.waitForTimeout(500);
  await page.screenshot({path: screenshot, fullPage: true});
  console.log('screenshot: ' + screenshot);
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
if (!process.exitCode) console.log('1 passed, 0 failed');
