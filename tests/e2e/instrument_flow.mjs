// End-to-end in a real browser (headless Debian chromium driven by playwright-core) against
// `labodrone serve` on the simulated lab: an admin uploads an instrument through the admin page (a
// panel photo drawn in the page) and places it on the east bench, where the simulated lab draws it at once; a student then inspects THAT instrument:
// the drone takes off, finds it (template matching far, SIFT near), flies to the standoff and holds
// it, and the page's reading view shows the uploaded panel rectified.
// Usage: node instrument_flow.mjs BASE_URL OUT_DIR
import {launchChromium, logIn} from './browser.mjs';

const [base, out] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await launchChromium();
const onPageError = (who) => (e) => fail(`${who}: page error: ${e.message}`);

try {
  const admin = (await logIn(browser, base, 'admin', 'admin-pass', {landing: /admin\.html$/, onPageError: onPageError('admin')})).page;
  // The panel's photo, drawn by the page's canvas: a display with large digits, knobs, buttons, a
  // label (a panel's kind of structure: it survives the far detector's downscaling, where a fine
  // random texture does not). 480 x 320 px for a 0.36 x 0.24 m panel.
  const pngBase64 = await admin.evaluate(() => {
    const c = document.createElement('canvas'); c.width = 480; c.height = 320;
    const g = c.getContext('2d');
    g.fillStyle = '#d9d4c7'; g.fillRect(0, 0, 480, 320);
    g.fillStyle = '#1d2b1f'; g.fillRect(24, 24, 270, 120);
    g.fillStyle = '#7cf07c'; g.font = 'bold 84px monospace'; g.fillText('12.34', 36, 120);
    g.fillStyle = '#20201e'; g.font = 'bold 30px sans-serif'; g.fillText('LABO DMM-3', 24, 200);
    const knob = (x, y, r, colour) => {
      g.fillStyle = colour; g.beginPath(); g.arc(x, y, r, 0, 2 * Math.PI); g.fill();
      g.fillStyle = '#f0f0f0'; g.fillRect(x - 4, y - r, 8, r);
    };
    knob(380, 90, 58, '#2a2a2a'); knob(90, 265, 34, '#b02020'); knob(200, 265, 34, '#2040b0');
    ['#e0a020', '#30a040', '#808080', '#c03070'].forEach((colour, i) => {
      g.fillStyle = colour; g.fillRect(300 + (i % 2) * 80, 180 + Math.floor(i / 2) * 70, 60, 45);
    });
    g.strokeStyle = '#20201e'; g.lineWidth = 6; g.strokeRect(3, 3, 474, 314);
    return c.toDataURL('image/png').split(',')[1];
  });
  await admin.fill('#i-id', 'bench_meter');
  await admin.fill('#i-name', 'Bench multimeter');
  await admin.fill('#i-w', '0.36');
  await admin.fill('#i-h', '0.24');
  await admin.fill('#i-x', '5.85');
  await admin.fill('#i-y', '0.8');
  await admin.fill('#i-z', '1.02');
  await admin.fill('#i-yaw', '180');
  await admin.setInputFiles('#i-photo', {name: 'bench_meter.png', mimeType: 'image/png', buffer: Buffer.from(pngBase64, 'base64')});
  await admin.click('#add-instrument button');
  await admin.waitForFunction(() => document.getElementById('i-result').textContent.length > 0, null, {timeout: 20000});
  const added = await admin.textContent('#i-result');
  console.log('admin: ' + added);
  if (!added.includes('inspectable now')) throw new Error(`the upload was not placed: '${added}'`);
  await admin.waitForFunction(() => document.getElementById('instruments').textContent.includes('bench_meter'));

  const student = (await logIn(browser, base, 'student1', 'student1-pass', {onPageError: onPageError('student1')})).page;
  await student.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});
  await student.waitForFunction(() => [...document.querySelectorAll('#instrument option')].some((o) => o.value === 'bench_meter'),
                                null, {timeout: 10000});
  await student.click('#request-control');
  await student.waitForFunction(() => document.getElementById('turn').textContent.includes('your turn'));
  await student.selectOption('#instrument', 'bench_meter');
  await student.click('#inspect');
  await student.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'inspect' && a.accepted));
  const t0 = Date.now();
  // Take-off, SLAM and its scale, the search, the approach: then the standoff held (the stage line
  // the telemetry carries: "3 inspect: holding ...").
  const seen = [];  // the stage line whenever its words before the counters change, for the log
  for (let held = false; !held;) {
    const line = await student.textContent('#stage');
    const words = line.replace(/[0-9.]+/g, '#');
    if (!seen.length || seen[seen.length - 1].words !== words) {
      seen.push({words, line});
      console.log(`  ${((Date.now() - t0) / 1000).toFixed(0)} s: ${line} (mission ${await student.textContent('#mission')})`);
    }
    held = line.includes('holding');
    if (!held && Date.now() - t0 > 200000) throw new Error('the standoff was never held');
    if (!held) await student.waitForTimeout(1000);
  }
  console.log(`student: '${await student.textContent('#stage')}' after ${((Date.now() - t0) / 1000).toFixed(0)} s; stages begun: ` +
              (await student.evaluate(() => [...new Set(window.labodrone.stages.filter((s) => s))].join(' | '))));
  if (!(await student.evaluate(() => window.labodrone.stages.some((s) => s && s.includes("'bench_meter'"))))) fail('no stage names the uploaded instrument');
  await student.waitForFunction(() => window.labodrone.readingViews > 0, null, {timeout: 10000})
    .catch(() => fail('the reading view of the uploaded panel never came'));
  await student.screenshot({path: out + '/instrument_student.png', fullPage: true});
  await student.click('#stop');
  await student.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'stop'));
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
if (!process.exitCode) console.log('PASS instrument_flow');
