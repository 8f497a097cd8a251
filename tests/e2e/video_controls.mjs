// End-to-end in a real browser (headless Debian chromium, playwright-core): the H.264 renditions and
// the bottom camera.
//  1. The page starts on the drone's stream and says so; the viewer picks the low rendition: the page
//     decodes the server's shared low rendition from its IDR on and says so; back to auto: the drone's
//     stream again.
//  2. The link throttled by Chromium's network emulation (CDP, THROTTLE_KBPS, default 2000): the
//     server moves the page to the low rendition by itself, and the page keeps its video flowing.
//     Only where the emulation reaches WebSockets and the drone's stream is faster than the throttle
//     (the simulated lab's is 4 Mbit/s); otherwise it says why it was skipped.
//  3. Holding control, the viewer selects the bottom camera: frames from the bottom camera are drawn
//     and the page says which camera it shows; then the front camera again.
// Frames/s below MIN_FPS (default 5: the video stopped) fail; the speed target is checked with
// MIN_FPS=25 as a benchmark run (docs/web.md), not in the suite, where the machine's load sets it.
// It saves video_low_rendition.png and video_bottom_camera.png.
// Usage: node video_controls.mjs BASE_URL OUT_DIR scripted|sim
import {launchChromium, logIn} from './browser.mjs';

const [base, outDir, mode] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const minFps = Number(process.env.MIN_FPS || 5);
const browser = await launchChromium();

const stats = (page) => page.evaluate(() => ({...window.labodrone, renditionFrames: {...window.labodrone.renditionFrames}}));
// Frames drawn per second over `ms`.
async function fps(page, ms) {
  const a = await stats(page);
  const t0 = Date.now();
  await page.waitForTimeout(ms);
  const b = await stats(page);
  return {fps: (b.framesDecoded - a.framesDecoded) * 1000 / (Date.now() - t0), low: b.renditionFrames.low - a.renditionFrames.low,
          source: b.renditionFrames.source - a.renditionFrames.source, after: b};
}

try {
  const {context, page} = await logIn(browser, base, 'student3', 'student3-pass',
                                      {onPageError: (e) => fail('page error: ' + e.message)});
  await page.waitForFunction(() => window.labodrone && window.labodrone.videoPath === 'h264', null, {timeout: 10000});
  await page.waitForFunction(() => window.labodrone.framesDecoded >= 30, null, {timeout: 20000});

  // 1. The viewer's choice of rendition.
  let s = await stats(page);
  if (s.rendition !== 'source') fail(`the page starts on ${s.rendition}, expected the drone's stream`);
  if (!(await page.textContent('#video-rendition')).includes("the drone's stream")) fail('the page does not say it shows the drone\'s stream');
  await page.selectOption('#video-rendition-choice', 'low');
  await page.waitForFunction(() => window.labodrone.rendition === 'low', null, {timeout: 5000});
  const low = await fps(page, 3000);
  console.log(`low rendition chosen: ${low.fps.toFixed(1)} frames/s in the page (${low.low} low, ${low.source} of the drone's stream), codec ${low.after.codec}`);
  if (low.fps < minFps) fail(`only ${low.fps.toFixed(1)} frames/s of the low rendition reached the page`);
  if (low.source > 0) fail('frames of the drone\'s stream were drawn after the switch to the low rendition');
  const lowText = await page.textContent('#video-rendition');
  if (!lowText.includes('low rendition') || !lowText.includes('chosen by the viewer')) fail(`the page says: ${lowText}`);
  await page.screenshot({path: `${outDir}/video_low_rendition.png`, fullPage: true});
  await page.selectOption('#video-rendition-choice', 'auto');
  await page.waitForFunction(() => window.labodrone.rendition === 'source', null, {timeout: 5000});
  console.log('auto: back on the drone\'s stream');

  // 2. A throttled link: the server moves the page down by itself.
  const kbps = Number(process.env.THROTTLE_KBPS || 2000);
  const cdp = await context.newCDPSession(page);
  await cdp.send('Network.enable');
  await cdp.send('Network.emulateNetworkConditions', {offline: false, latency: 20, downloadThroughput: kbps * 125, uploadThroughput: kbps * 125});
  // The server sees the throttle only once the bytes between its socket and the emulation are full:
  // the browser's TCP receive buffer, which the kernel's autotuning grew while the page read at full
  // speed (megabytes on loopback), fills at the stream's excess over the throttle (2 Mbit/s here), so
  // the move comes after seconds that depend on how far the autotuning went: about 10 s on a loaded
  // machine, hence 40 s allowed. The move itself is the behaviour checked, not its delay.
  const throttledAt = Date.now();
  const moved = await page.waitForFunction(() => window.labodrone.renditionTarget === 'low', null, {timeout: 40000}).then(() => true, () => false);
  if (moved) {
    const after_s = ((Date.now() - throttledAt) / 1000).toFixed(1);
    await page.waitForFunction(() => window.labodrone.rendition === 'low', null, {timeout: 5000});
    const throttled = await fps(page, 10000);
    console.log(`throttled to ${kbps} kbit/s: moved to the low rendition after ${after_s} s (${throttled.after.renditionReason}); ` +
                `${throttled.fps.toFixed(1)} frames/s in the page over 10 s`);
    if (throttled.fps < minFps) fail(`a page on a ${kbps} kbit/s link kept only ${throttled.fps.toFixed(1)} frames/s`);
  } else if (mode === 'sim') {
    fail(`throttled to ${kbps} kbit/s, the page stayed on the drone's stream (${(await stats(page)).renditionReason})`);
  } else {
    console.log(`throttled to ${kbps} kbit/s: the test card's stream fits, no move (skipped: the simulated lab's run checks it)`);
  }
  await cdp.send('Network.emulateNetworkConditions', {offline: false, latency: 0, downloadThroughput: -1, uploadThroughput: -1});

  // 3. The bottom camera, with control.
  await page.click('#request-control');
  await page.waitForFunction(() => document.getElementById('turn').textContent.includes('your turn'), null, {timeout: 5000});
  s = await stats(page);
  if (!s.videoInfo || !s.videoInfo.bottom_camera) fail(`the drone offers no bottom camera: ${JSON.stringify(s.videoInfo)}`);
  await page.selectOption('#video-camera', 'bottom');
  await page.waitForFunction(() => window.labodrone.acks.some((a) => a.command === 'select_camera' && a.accepted), null, {timeout: 5000});
  await page.waitForFunction(() => window.labodrone.camera === 'bottom', null, {timeout: 10000});
  await page.waitForTimeout(500);
  if ((await page.textContent('#video-camera-shown')) !== 'bottom') fail('the page does not say it shows the bottom camera');
  console.log('bottom camera selected: its frames are drawn');
  await page.screenshot({path: `${outDir}/video_bottom_camera.png`, fullPage: true});
  await page.selectOption('#video-camera', 'front');
  await page.waitForFunction(() => window.labodrone.camera === 'front', null, {timeout: 10000});
  console.log('front camera again');
  console.log(`screenshots: ${outDir}/video_low_rendition.png, ${outDir}/video_bottom_camera.png`);
  await context.close();
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
if (!process.exitCode) console.log('1 passed, 0 failed');
