// End-to-end in a real browser (headless Debian chromium, playwright-core): the two video paths.
//  1. WebCodecs present: the page takes the H.264 path, decodes the drone's access units, draws the
//     overlays from the geometry sent with each frame, and stops drawing a group switched off;
//  2. WebCodecs removed (an init script deletes window.VideoDecoder): the page falls back to JPEG.
// With the scripted flight it also waits for the instrument reading view (the panel rectified by the
// server) and saves it as reading_view.png.
// It prints frames/s and the glass-to-browser latency (median, p95) of each path, and saves a
// screenshot of each. Usage: [MEASURE_S=5] node video_paths.mjs BASE_URL OUT_DIR scripted|sim
//   scripted: labo_e2e_server, whose scripted flight always reports a panel at (220,100)-(420,220):
//             the outline is checked in the canvas' pixels; sim: labodrone serve (no panel in view
//             on the platform, so only the decoding, the border and the HUD are checked).
import {launchChromium, logIn} from './browser.mjs';

// The test checks that video flows; the frame-rate target (>= 25 frames/s) is checked by the
// benchmark run of the same script with MIN_FPS=25 (docs/web.md), on a machine doing nothing else.
const minFps = Number(process.env.MIN_FPS || 5);

const [base, outDir, mode] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await launchChromium();

async function openLab(initScript) {
  const {context, page} = await logIn(browser, base, 'student2', 'student2-pass',
                                      {onPageError: (e) => fail('page error: ' + e.message), initScript});
  await page.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});
  return {context, page};
}

// Frames/s and latency over MEASURE_S seconds (default 5), once 30 frames were drawn (the start-up
// left out).
async function measure(page, label, ms = 1000 * Number(process.env.MEASURE_S || 5)) {
  await page.waitForFunction(() => window.labodrone.framesDecoded >= 30, null, {timeout: 20000});
  const t0 = await page.evaluate(() => {
    window.labodrone.resetLatencies();
    return {n: window.labodrone.framesDecoded, t: performance.now()};
  });
  await page.waitForTimeout(ms);
  const s = await page.evaluate(() => ({n: window.labodrone.framesDecoded, t: performance.now(),
                                         latency: window.labodrone.latencySummary(), ...window.labodrone}));
  const fps = (s.n - t0.n) * 1000 / (s.t - t0.t);
  console.log(`${label}: ${fps.toFixed(1)} frames/s in the page; glass-to-browser latency median ` +
              `${s.latency.median.toFixed(0)} ms, p95 ${s.latency.p95.toFixed(0)} ms (${s.latency.frames} frames)`);
  if (fps < minFps) fail(`${label}: only ${fps.toFixed(1)} frames/s reached the page`);
  return s;
}

// The canvas pixel at (x, y) as [r, g, b].
const pixel = (page, x, y) => page.evaluate(([px, py]) =>
  Array.from(document.getElementById('video').getContext('2d').getImageData(px, py, 1, 1).data.slice(0, 3)), [x, y]);
const isCyan = ([r, g, b]) => r < 90 && g > 190 && b > 190;

try {
  // 1. H.264 through WebCodecs, overlays drawn in the page.
  const {context, page} = await openLab(null);
  await page.waitForFunction(() => window.labodrone.videoPath === 'h264', null, {timeout: 10000});
  const h264 = await measure(page, 'H.264 path');
  if (!/^avc1\.42/.test(h264.codec || '')) fail(`expected H.264 Baseline (avc1.42...), the page configured ${h264.codec}`);
  if (!(await page.textContent('#video-path')).includes('WebCodecs')) fail('the page does not say it decodes H.264 itself');
  for (const group of ['border', 'hud', ...(mode === 'scripted' ? ['panel'] : [])])
    if (!h264.overlaysDrawn.includes(group)) fail(`overlay group ${group} not drawn (drawn: ${h264.overlaysDrawn})`);
  if (mode === 'scripted' && !isCyan(await pixel(page, 320, 100))) fail('no cyan panel outline at (320, 100)');
  await page.screenshot({path: `${outDir}/video_h264.png`, fullPage: true});
  if (mode === 'scripted') {
    // The scripted panel, rectified by the server to its 400x240 template resolution.
    await page.waitForFunction(() => window.labodrone.readingViews >= 3, null, {timeout: 5000});
    const size = await page.evaluate(() => [document.getElementById('reading-view').width, document.getElementById('reading-view').height]);
    if (size[0] !== 400 || size[1] !== 240) fail(`the reading view is ${size}, expected the template's 400x240`);
    await page.locator('#reading').screenshot({path: `${outDir}/reading_view.png`});
  }

  // One group off: the next frames are drawn without it, the others still with.
  await page.uncheck('#overlay-border');
  if (mode === 'scripted') await page.uncheck('#overlay-panel');
  const before = await page.evaluate(() => window.labodrone.framesDecoded);
  await page.waitForFunction((n) => window.labodrone.framesDecoded >= n + 10, before, {timeout: 5000});
  const off = await page.evaluate(() => window.labodrone.overlaysDrawn);
  if (off.includes('border') || off.includes('panel')) fail(`a group switched off is still drawn (drawn: ${off})`);
  if (!off.includes('hud')) fail(`the HUD went with the border (drawn: ${off})`);
  if (mode === 'scripted' && isCyan(await pixel(page, 320, 100))) fail('the panel outline is still drawn once switched off');
  console.log(`overlays drawn with the border${mode === 'scripted' ? ' and the panel' : ''} off: ${off.join(', ')}`);
  await context.close();

  // 2. No WebCodecs: the page falls back to the JPEG path by itself.
  const jpeg = await openLab(() => { delete window.VideoDecoder; });
  await jpeg.page.waitForFunction(() => window.labodrone.videoPath === 'jpeg', null, {timeout: 10000});
  const j = await measure(jpeg.page, 'JPEG fallback');
  if (!j.videoPathReason.includes('WebCodecs')) fail(`the fallback does not say why: ${j.videoPathReason}`);
  if (!(await jpeg.page.isDisabled('#overlay-panel'))) fail('overlay toggles stay enabled on the JPEG path (overlays are burnt in)');
  await jpeg.page.screenshot({path: `${outDir}/video_jpeg_fallback.png`, fullPage: true});
  await jpeg.context.close();
  console.log(`screenshots: ${outDir}/video_h264.png, ${outDir}/video_jpeg_fallback.png`);
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
if (!process.exitCode) console.log('1 passed, 0 failed');
