// End-to-end in a real browser (headless Debian chromium, playwright-core): the video through Janus.
// Against labs started by scripts/janus/run_labs.sh (Janus with a mount point per lab, each
// `labodrone serve --rtp-video` to it, a shared session key): log in at lab 1, see the page take its
// video from Janus over WebRTC and the overlay geometry from the mount point's data channel (the
// page's WebSocket then on the 'none' path), decode frames and draw their overlays matched by RTP
// timestamp (the HUD and the source border are in every frame's geometry); open lab 2 with the same login
// (no second login: the session is valid there too) and see its video through its own mount point;
// lab 2 sends no geometry to its mount point's data channel (run_janus_test.sh), so its page must fall
// back to the geometry over its WebSocket and still match it to the frames.
// Prints frames/s, glass-to-browser latency and the frames presented without geometry.
// Usage: [MEASURE_S=5] node janus_view.mjs LAB1_URL LAB2_URL OUT_DIR
import {launchChromium, logIn} from './browser.mjs';

// The test checks that video flows; the frame-rate target (>= 25 frames/s) is checked by the
// benchmark run of the same script with MIN_FPS=25 (docs/web.md), on a machine doing nothing else.
const minFps = Number(process.env.MIN_FPS || 5);

const [lab1, lab2, outDir] = process.argv.slice(2);
const fail = (msg) => { console.error('FAIL: ' + msg); process.exitCode = 1; };
const browser = await launchChromium(['--autoplay-policy=no-user-gesture-required']);

async function janusFrames(page, label, geometrySource = 'data channel') {
  await page.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});
  try {
    await page.waitForFunction(() => window.labodrone.videoPath === 'janus' || window.labodrone.janusReason,
                               null, {timeout: 15000});
  } catch (e) { /* reported below */ }
  const path = await page.evaluate(() => [window.labodrone.videoPath, window.labodrone.janusReason]);
  if (path[0] !== 'janus') return fail(`${label}: the page did not take the Janus path: ${path[0]} (${path[1]})`);
  await page.waitForFunction(() => window.labodrone.framesDecoded >= 30, null, {timeout: 20000});
  if (geometrySource === 'data channel') {
    await page.waitForFunction(() => window.labodrone.geometrySource === 'data channel', null, {timeout: 10000})
        .catch(async () => fail(`${label}: the geometry did not come over Janus's data channel (from: ${await page.evaluate(() => window.labodrone.geometrySource)})`));
  }
  const t0 = await page.evaluate(() => {
    window.labodrone.resetLatencies();
    return {n: window.labodrone.framesDecoded, t: performance.now()};
  });
  await page.waitForTimeout(1000 * Number(process.env.MEASURE_S || 5));
  const s = await page.evaluate(() => ({n: window.labodrone.framesDecoded, t: performance.now(),
                                         latency: window.labodrone.latencySummary(), ...window.labodrone}));
  const fps = (s.n - t0.n) * 1000 / (s.t - t0.t);
  console.log(`${label}: ${fps.toFixed(1)} frames/s through Janus; glass-to-browser latency median ` +
              `${s.latency.median.toFixed(0)} ms, p95 ${s.latency.p95.toFixed(0)} ms; ` +
              `overlays (geometry from the ${s.geometrySource}) matched by RTP timestamp on ${s.janusMatched || 0} frames, ` +
              `${s.janusUnmatched || 0} without`);
  if (fps < minFps) fail(`${label}: only ${fps.toFixed(1)} frames/s reached the page`);
  if (s.geometrySource !== geometrySource) fail(`${label}: the geometry came from the ${s.geometrySource}, expected the ${geometrySource}`);
  const matched = (s.janusMatched || 0) / Math.max(1, (s.janusMatched || 0) + (s.janusUnmatched || 0));
  if (matched < 0.7) fail(`${label}: only ${(100 * matched).toFixed(0)} % of the frames found their geometry`);
  // Every frame's geometry has the HUD and the source border: the last matched frame drew them.
  const drawn = await page.evaluate(() => window.labodrone.overlaysDrawn);
  await page.waitForFunction(() => window.labodrone.overlaysDrawn.includes('hud') && window.labodrone.overlaysDrawn.includes('border'),
                             null, {timeout: 5000}).catch(() => fail(`${label}: overlays not drawn: ${JSON.stringify(drawn)}`));
  if (!(await page.textContent('#video-path')).includes('Janus')) fail(`${label}: the page does not say its video comes through Janus`);
  return s;
}

try {
  const {context, page} = await logIn(browser, lab1, 'student2', 'student2-pass',
                                      {onPageError: (e) => fail('page error: ' + e.message)});
  await janusFrames(page, 'lab 1');
  await page.screenshot({path: outDir + '/janus_lab1.png'});

  // The lab list, then lab 2 with the same session (the cookie is per host, the key shared).
  await page.goto(lab1 + '/labs.html');
  await page.waitForSelector('#labs li');
  const links = await page.$$eval('#labs a', (as) => as.map((a) => a.href));
  if (links.length !== 2) fail(`the lab list has ${links.length} labs, expected 2`);
  const other = await context.newPage();
  other.on('pageerror', (e) => fail('page error: ' + e.message));
  await other.goto(lab2 + '/lab.html');
  await other.waitForFunction(() => window.labodrone && window.labodrone.connected, null, {timeout: 10000});
  if (!other.url().endsWith('/lab.html')) fail('lab 2 asked for a second login');
  await janusFrames(other, 'lab 2', 'websocket');
} catch (e) {
  fail(e.message);
} finally {
  await browser.close();
}
