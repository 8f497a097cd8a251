// The Janus fan-out under load (a benchmark, run by scripts/janus/load_bench.sh): while a pilot holds
// control and has taken off (its page on the direct WebSocket path), N spectators in headless
// Chromium watch the lab through Janus (WebRTC). The first is the lab page (it decodes and draws);
// the others are receive-only viewers: a full WebRTC session with Janus (ICE, DTLS-SRTP, RTCP) whose
// encoded frames are counted and dropped before the decoder by an insertable-streams transform, and
// LaboDrone's WebSocket with the geometry subscription, as the lab page has. Decoding is each
// spectator's own machine's work; on this 2-core machine N decoders would measure Chromium, not the
// fan-out. For each N of the list, once every viewer gets frames:
// frames/s per viewer over SECONDS, and over the same window the CPU of LaboDrone, Janus and Chromium
// (from /proc) and the pilot's glass-to-client latency measured by labo_web_bench (one direct H.264
// WebSocket client, not in the browser, so the browser's load does not enter it).
// Usage: node janus_load.mjs BASE_URL LABO_PID JANUS_PID WEB_BENCH "1 5 10" SECONDS
import {execFile} from 'node:child_process';
import {readFileSync, readdirSync} from 'node:fs';
import {promisify} from 'node:util';
import {chromium} from 'playwright-core';

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

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync',
         '--autoplay-policy=no-user-gesture-required', '--disable-background-timer-throttling',
         '--disable-renderer-backgrounding', '--disable-backgrounding-occluded-windows'],
});

async function login(user) {
  const context = await browser.newContext({viewport: {width: 1480, height: 900}});
  const page = await context.newPage();
  await page.goto(base + "/", {timeout: 120000});
  await page.fill('#user', user);
  await page.fill('#password', user + '-pass');
  await page.click('#login-button');
  await page.waitForURL('**/lab.html');
  return {context, page};
}

// Receive-only viewers, all in one page (one renderer process for them all; each its own Janus
// session and peer connection and its own WebSocket to LaboDrone, as separate spectators have).
async function addLightViewer(page, mountpoint, janusUrl) {
  await page.evaluate(async ([id, url]) => {
    const load = (src) => new Promise((ok, ko) => { const s = document.createElement('script'); s.src = src; s.onload = ok; s.onerror = ko; document.head.append(s); });
    if (!window.Janus) {
      await load('/vendor/adapter.js');
      await load('/vendor/janus.js');
      await new Promise((ok) => Janus.init({debug: false, callback: ok}));
      window.lights = [];
    }
    const me = {frames: 0, overlays: 0, bytes: 0};
    window.lights.push(me);
    const ws = new WebSocket(`ws://${location.host}/ws`);
    ws.onopen = () => ws.send(JSON.stringify({type: 'subscribe', video: 'geometry'}));
    ws.onmessage = (ev) => { if (typeof ev.data === 'string' && ev.data.startsWith('{"type":"overlay"')) me.overlays++; };
    const counted = (f) => { me.frames++; me.bytes += f.data.byteLength; };
    // A receiver transform makes janus.js create the peer connection with encoded insertable
    // streams; the encoded frames are then read here, counted and dropped (never decoded).
    const counter = new TransformStream({transform: counted});
    const readEncoded = (pc) => {
      for (const r of pc.getReceivers()) {
        if (r.track.kind !== 'video') continue;
        try { r.createEncodedStreams().readable.pipeTo(new WritableStream({write: counted})); } catch (e) { /* read through `counter` */ }
      }
    };
    const session = new Janus({server: url.replace('{host}', location.hostname), success: () => session.attach({
      plugin: 'janus.plugin.streaming',
      success: (h) => { me.handle = h; h.send({message: {request: 'watch', id}}); },
      webrtcState: (up) => { if (up) readEncoded(me.handle.webrtcStuff.pc); },
      onmessage: (msg, jsep) => {
        if (!jsep) return;
        me.handle.createAnswer({jsep, tracks: [{type: 'video', recv: true, transforms: {receiver: counter}}],
          success: (answer) => me.handle.send({message: {request: 'start'}, jsep: answer})});
      },
    })});
  }, [mountpoint, janusUrl]);
}

// Frames so far: the lab page's drawn frames, then each receive-only viewer's encoded frames read
// by its page (a starved renderer reads them late: the count is what the page got).
const frameCounts = async (labPage, lightPage) => [await labPage.evaluate(() => window.labodrone.framesDecoded),
  ...await lightPage.evaluate(() => (window.lights || []).map((l) => l.frames))];
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
  // Its own window (a second tab of the lab page's would hide it, and a hidden page draws no frames),
  // logged in: the viewers' WebSockets need the session.
  const lightPage = (await login('student2')).page;
  await lightPage.goto(base + '/labs.html', {timeout: 120000});
  let count = 1;

  for (const n of counts.split(/\s+/).map(Number)) {
    for (; count < n; ++count) await addLightViewer(lightPage, janus.mountpoint, janus.url);
    await spectators.page.waitForFunction(() => window.labodrone.framesDecoded >= 30, null, {timeout: 120000});
    for (const until = Date.now() + 300000; ;) {
      const received = (await frameCounts(spectators.page, lightPage)).slice(1);
      if (received.every((f) => f >= 30)) break;
      if (Date.now() > until) throw new Error(`receive-only viewers without 30 frames after 300 s: ${received}`);
      await new Promise((ok) => setTimeout(ok, 1000));
    }
    const f0 = await frameCounts(spectators.page, lightPage);
    const c0 = {labo: cpuSeconds(laboPid), janus: cpuSeconds(janusPid), chromium: browserCpu()};
    const t0 = performance.now();
    const {stdout} = await promisify(execFile)(webBench, [port, laboPid, '1', seconds, '0', 'h264']);
    const wall = (performance.now() - t0) / 1000;
    const c1 = {labo: cpuSeconds(laboPid), janus: cpuSeconds(janusPid), chromium: browserCpu()};
    const f1 = await frameCounts(spectators.page, lightPage);
    const fps = f1.map((f, i) => (f - f0[i]) / wall);
    const light = fps.slice(1).sort((a, b) => a - b);
    const cores = (key) => ((c1[key] - c0[key]) / wall).toFixed(3);
    const pilotLatency = (stdout.match(/latency ms: (.*)/) || [])[1];
    const page = await spectators.page.evaluate(() => window.labodrone.latencySummary());
    const overlays = await lightPage.evaluate(() => (window.lights || []).map((l) => l.overlays));
    console.log(`viewers ${n}: the lab page (decodes, draws) ${fps[0].toFixed(1)} frames/s, glass-to-browser median ` +
                `${page.median.toFixed(0)} ms; ${light.length} receive-only: frames/s min ` +
                `${light.length ? light[0].toFixed(1) : '-'}, median ${light.length ? light[Math.floor(light.length / 2)].toFixed(1) : '-'}` +
                `${light.length ? `, overlays received min ${Math.min(...overlays)}` : ''}; CPU cores: labodrone ${cores('labo')}, ` +
                `janus ${cores('janus')}, chromium ${cores('chromium')}; pilot (direct H.264, labo_web_bench) latency ${pilotLatency}`);
  }
} catch (e) {
  console.error('FAIL: ' + e.message);
  process.exitCode = 1;
} finally {
  await browser.close();
}
