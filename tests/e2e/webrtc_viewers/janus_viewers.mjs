// Receive-only WebRTC viewers of a Janus streaming mount point, without a browser (werift, a WebRTC
// stack in Node.js): each its own Janus session over Janus's WebSocket API, its own peer connection
// (ICE, DTLS-SRTP) and data channel. A viewer counts the frames it receives (RTP packets with the
// marker bit: the last of each access unit) and the geometries its data channel delivers (first
// parts, "LDG1 <frame> 0 "); nothing is decoded. With LAB_WS_URL and COOKIE each viewer also holds
// LaboDrone's WebSocket on the 'none' path (telemetry and events), as a spectator's page does, and
// counts the messages it reads there. For the Janus fan-out benchmark (tests/e2e/janus_load.mjs),
// which drives it over stdin/stdout:
//   node janus_viewers.mjs JANUS_WS_URL MOUNTPOINT [LAB_WS_URL COOKIE]
//   stdin: "add N" (N more viewers), "counts"; each answered by one JSON line:
//          [[frames, geometries, lab messages], ...] per viewer
// Each viewer keeps its Janus session alive (keepalive every 20 s); all end with stdin.
import {createInterface} from 'node:readline';
import {RTCPeerConnection, RTCRtpCodecParameters} from 'werift';
import WebSocket from 'ws';

const [url, mountpoint, labUrl, cookie] = process.argv.slice(2);
const viewers = [];
let transactions = 0;

// One request on the viewer's Janus WebSocket; resolves with the first reply of its transaction
// that is not an "ack".
function request(v, message) {
  const transaction = String(++transactions);
  return new Promise((resolve, reject) => {
    v.pending.set(transaction, {resolve, reject});
    v.ws.send(JSON.stringify({...message, transaction, session_id: v.session, handle_id: v.handle}));
  });
}

async function addViewer() {
  const v = {frames: 0, geometries: 0, labMessages: 0, pending: new Map(), session: undefined, handle: undefined};
  if (labUrl) {
    v.lab = new WebSocket(labUrl, {headers: {Cookie: cookie}});
    await new Promise((ok, ko) => { v.lab.once('open', ok); v.lab.once('error', ko); });
    v.lab.send(JSON.stringify({type: 'subscribe', video: 'none'}));
    v.lab.on('message', () => v.labMessages++);
  }
  v.ws = new WebSocket(url, 'janus-protocol');
  await new Promise((ok, ko) => { v.ws.once('open', ok); v.ws.once('error', ko); });
  v.ws.on('message', (data) => onJanus(v, JSON.parse(data.toString())));
  v.session = (await request(v, {janus: 'create'})).data.id;
  v.handle = (await request(v, {janus: 'attach', plugin: 'janus.plugin.streaming'})).data.id;
  v.keepalive = setInterval(() => v.ws.send(JSON.stringify({janus: 'keepalive', session_id: v.session, transaction: 'k'})), 20000);
  // The mount point's H.264 (scripts/janus/janus_config.sh); werift offers VP8 only by default.
  v.pc = new RTCPeerConnection({codecs: {audio: [], video: [new RTCRtpCodecParameters({
    mimeType: 'video/H264', clockRate: 90000, parameters: 'profile-level-id=42e01f;packetization-mode=1'})]}});
  v.pc.onTransceiverAdded.subscribe((t) => t.onTrack.subscribe((track) =>
    track.onReceiveRtp.subscribe((rtp) => { if (rtp.header.marker) v.frames++; })));
  const countGeometry = (m) => { if (/^LDG1 \d+ 0 /.test(Buffer.from(m).subarray(0, 24).toString())) v.geometries++; };
  v.pc.onDataChannel.subscribe((channel) => channel.onMessage.subscribe(countGeometry));
  v.pc.onIceCandidate.subscribe((c) => {
    const candidate = c ? {candidate: c.candidate, sdpMid: c.sdpMid, sdpMLineIndex: c.sdpMLineIndex} : {completed: true};
    v.ws.send(JSON.stringify({janus: 'trickle', candidate, session_id: v.session, handle_id: v.handle, transaction: 't'}));
  });
  const offer = await request(v, {janus: 'message', body: {request: 'watch', id: Number(mountpoint)}});
  if (!offer.jsep) throw new Error('no offer from the mount point: ' + JSON.stringify(offer.plugindata));
  await v.pc.setRemoteDescription(offer.jsep);
  // Janus relays the mount point's data on the channel the viewer opens (as janus.js does).
  v.pc.createDataChannel('JanusDataChannel').onMessage.subscribe(countGeometry);
  const answer = await v.pc.createAnswer();
  await v.pc.setLocalDescription(answer);
  await request(v, {janus: 'message', body: {request: 'start'}, jsep: {type: 'answer', sdp: v.pc.localDescription.sdp}});
  viewers.push(v);
}

function onJanus(v, msg) {
  if (msg.janus === 'trickle' && msg.candidate && !msg.candidate.completed) {
    v.pc.addIceCandidate(msg.candidate).catch(() => {});
    return;
  }
  if (msg.janus === 'ack' || !msg.transaction || !v.pending.has(msg.transaction)) return;
  const p = v.pending.get(msg.transaction);
  v.pending.delete(msg.transaction);
  if (msg.janus === 'error') p.reject(new Error(msg.error.reason));
  else p.resolve(msg);
}

const input = createInterface({input: process.stdin});
for await (const line of input) {
  const [command, n] = line.trim().split(/\s+/);
  try {
    if (command === 'add') for (let i = 0; i < Number(n); ++i) await addViewer();
    if (command === 'counts' || command === 'add') console.log(JSON.stringify(viewers.map((v) => [v.frames, v.geometries, v.labMessages])));
  } catch (e) {
    console.log(JSON.stringify({error: e.message}));
  }
}
for (const v of viewers) {
  clearInterval(v.keepalive);
  v.pc.close();
  v.ws.close();
  if (v.lab) v.lab.close();
}
process.exit(0);
