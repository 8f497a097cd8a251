// The Janus fan-out under load (a benchmark, run by scripts/janus/load_bench.sh): while a pilot holds
// control and has taken off (its page on the direct WebSocket path, in headless Chromium), N
// spectators watch the lab through Janus. The first is the lab page in Chromium (it decodes and
// draws); the others are receive-only viewers outside the browser (webrtc_viewers/janus_viewers.mjs,
// werift in one Node.js process): each a full WebRTC session with Janus (ICE, DTLS-SRTP, RTCP and the
// data channel with the geometry) and LaboDrone's WebSocket on the 'none' path, as a spectator's page
// has; their frames are counted, not decoded. Decoding is each spectator's own machine's work, and
// on this 2-core machine N Chromium peer connections would measure Chromium, not the fan-out.
// For each N of the list, once every viewer gets frames: frames/s and geometries/s per viewer over
// SECONDS, and over the same window the CPU of LaboDrone, Janus, the viewers' process and Chromium
// (from /proc), and the pilot's glass-to-client latency measured by labo_web_bench (one direct H.264
// WebSocket client, not in the browser, so the browser's load does not enter it).
// Usage: node janus_load.mjs BASE_URL LABO_PID JANUS_PID WEB_BENCH "1 5 10" SECONDS
import {execFile, spawn} from 'node:child_process';
import {readFileSync, readdirSync} from 'node:fs';
import {createInterface} from 'node:readline';
import {promisify} from 'node:util';
import {launchChromium, logIn} from './browser.mjs';

const [base, laboPid, janusPid, webBench, counts, seconds] = process.argv.slice(2);
const port = new URL(base).port;
const ticks = 100;  // USER_HZ
const cpuSeconds = (pid) => {
  try {
    const f = readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
    return (Number(f[11]) + Number(f[12])) / ticks;  // utime + stime
  } catch (e) { return 0; }
};
// Every Chromium process (the browser and its renderers, GPU and utility processes).
const chromiumPids = () => readdirSync('/proc').filter((p) => /^\d+$/.test(p)).filter((p) => {
  try { return readFileSync(`/proc/${p}/comm`, 'utf8').startsWith('chrom'); } catch (e) { return false; }
});
const browserCpu = () => chromiumPids().reduce((sum, p) => sum + cpuSeconds(p), 0);

const browser = await launchChromium(['--autoplay-policy=no-user-gesture-required', '--disable-background-timer-throttling',
                                      '--disable-renderer-backgrounding', '--disable-backgrounding-occluded-windows']);

const login = (user) => logIn(browser, base, user, user + '-pass', {gotoOptions: {timeout: 120000}});

// The receive-only viewers' process: one request, one JSON line back.
function startViewers(janusUrl, mountpoint, cookie) {
  const child = spawn(process.execPath, [new URL('./webrtc_viewers/janus_viewers.mjs', import.meta.url).pathname,
                                         janusUrl, String(mountpoint), base.replace(/^http/, 'ws') + '/ws', cookie],
                      {stdio: ['pipe', 'pipe', 'inherit']});
  const lines = createInterface({input: child.stdout})[Symbol.asyncIterator]();
  const ask = async (command) => {
    child.stdin.write(command + '\n');
    const {value} = await lines.next();
    const reply = JSON.parse(value);
    if (reply.error) throw new Error('receive-only viewers: ' + reply.error);
    return reply;  // [[frames, geometries, lab messages], ...]
  };
  return {child, ask};
}

const rate = (after, before, wall) => after.map((x, i) => (x - (before[i] || 0)) / wall);
const sorted = (xs) => [...xs].sort((a, b) => a - b);
const fmt = (x) => x.toFixed(1);
let viewers = null;
try {
  // The pilot: control, take off, on the direct path (lowest latency).
  const pilot = await login('student1');
  await pilot.page.goto(base + '/lab.html?video=direct');
  await pilot.page.waitForFunction(() => window.labodrone.connected, null, {timeout: 10000});
  await pilot.page.click('#request-control');
  await pilot.page.waitForFunction(() => document.getElementById('turn').textContent.startsWith('you'), null, {timeout: 10000});
  await pilot.page.click('button[data-command="takeoff"]');
  const spectators = await login('student3');
  await spectators.page.waitForFunction(() => window.labodrone.videoPath === 'janus', null, {timeout: 15000});
  const dir = await spectators.page.evaluate(async () => (await fetch('/api/labs')).json());
  const janus = dir.labs.find((l) => l.id === dir.self).janus;
  const cookie = (await spectators.context.cookies()).map((c) => `${c.name}=${c.value}`).join('; ');
  viewers = startViewers(janus.url.replace('{host}', new URL(base).hostname), janus.mountpoint, cookie);
  let count = 1;

  for (const n of counts.split(/\s+/).map(Number)) {
    if (n > count) await viewers.ask(`add ${n - count}`);
    count = Math.max(count, n);
    await spectators.page.waitForFunction(() => window.labodrone.framesDecoded >= 30, null, {timeout: 120000});
    for (const until = Date.now() + 120000; ;) {
      const received = (await viewers.ask('counts')).map((v) => v[0]);
      if (received.every((f) => f >= 30)) break;
      if (Date.now() > until) throw new Error(`receive-only viewers without 30 frames after 120 s: ${received}`);
      await new Promise((ok) => setTimeout(ok, 1000));
    }
    const page0 = await spectators.page.evaluate(() => window.labodrone.framesDecoded);
    const v0 = await viewers.ask('counts');
    const c0 = {labo: cpuSeconds(laboPid), janus: cpuSeconds(janusPid), viewers: cpuSeconds(viewers.child.pid), chromium: browserCpu()};
    const t0 = performance.now();
    const {stdout} = await promisify(execFile)(webBench, [port, laboPid, '1', seconds, '0', 'h264']);
    const wall = (performance.now() - t0) / 1000;
    const c1 = {labo: cpuSeconds(laboPid), janus: cpuSeconds(janusPid), viewers: cpuSeconds(viewers.child.pid), chromium: browserCpu()};
    const v1 = await viewers.ask('counts');
    const pageFps = (await spectators.page.evaluate(() => window.labodrone.framesDecoded) - page0) / wall;
    const frames = sorted(rate(v1.map((v) => v[0]), v0.map((v) => v[0]), wall));
    const geometries = sorted(rate(v1.map((v) => v[1]), v0.map((v) => v[1]), wall));
    const labMessages = sorted(rate(v1.map((v) => v[2]), v0.map((v) => v[2]), wall));
    const cores = (key) => ((c1[key] - c0[key]) / wall).toFixed(3);
    const pilotLatency = (stdout.match(/latency ms: (.*)/) || [])[1];
    // The drone's frame rate as the pilot receives it: the simulated lab renders in LaboDrone's
    // process, so a loaded machine lowers it, and LaboDrone's CPU with it.
    const sourceFps = (stdout.match(/frames\/s per client: min ([\d.]+)/) || [])[1];
    const page = await spectators.page.evaluate(() => ({...window.labodrone.latencySummary(), source: window.labodrone.geometrySource}));
    const spread = (xs) => xs.length ? `min ${fmt(xs[0])}, median ${fmt(xs[Math.floor(xs.length / 2)])}` : '-';
    console.log(`viewers ${n}: the lab page (decodes, draws) ${fmt(pageFps)} frames/s, glass-to-browser median ` +
                `${page.median.toFixed(0)} ms, geometry from the ${page.source}; ${frames.length} receive-only: frames/s ` +
                `${spread(frames)}; geometries/s (data channel) ${spread(geometries)}; LaboDrone WebSocket messages/s ` +
                `${spread(labMessages)}; CPU cores: labodrone ${cores('labo')}, janus ${cores('janus')}, receive-only ` +
                `viewers ${cores('viewers')}, chromium ${cores('chromium')}; pilot (direct H.264, labo_web_bench) ${sourceFps} frames/s, ` +
                `latency ${pilotLatency}`);
  }
} catch (e) {
  console.error('FAIL: ' + e.message);
  process.exitCode = 1;
} finally {
  if (viewers) viewers.child.stdin.end();
  await browser.close();
}
