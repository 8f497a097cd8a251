// A recording played back by the server (docs/web.md, "WebSocket protocol"): its frames ("LDP1":
// the 24-byte header of the live frames with the recording's time in place of the capture time, then
// a JPEG with the recorded navdata drawn in) on a canvas of their own, never over the live video, and
// its "replay" events as the caption. The lab page shows one when a replay is sent to everyone (or to
// this admin's connections); the admin page has its own.
import {drawAtOwnSize} from './reading_view.js';

const LDP1 = 0x3150444c;

export function isReplayFrame(buffer) {
  return buffer.byteLength >= 24 && new DataView(buffer).getUint32(0, true) === LDP1;
}

export class ReplayView {
  // `section` holds a canvas and an element with class "replay-caption"; hidden until a replay comes.
  constructor(section, stats) {
    this.section = section;
    this.canvas = section.querySelector('canvas');
    this.caption = section.querySelector('.replay-caption');
    this.stats = stats;
    Object.assign(stats, {replayFrames: 0, replayState: null, replayName: null, replayPositionS: 0});
    const close = section.querySelector('.replay-close');
    if (close) close.onclick = () => { this.section.hidden = true; };
  }

  async show(buffer) {
    const dv = new DataView(buffer);
    await drawAtOwnSize(this.canvas, buffer);
    this.stats.replayFrames++;
    this.stats.replayPositionS = dv.getFloat64(8, true) / 1000;
    if (this.stats.replayState !== 'playing') return;  // a frame still on its way after the stop
    this.section.hidden = false;
  }

  onMessage(msg) {
    Object.assign(this.stats, {replayState: msg.state, replayName: msg.name, replayPositionS: msg.position_s});
    const to = msg.audience === 'everyone' ? 'to everyone' : `to ${msg.by}`;
    let text = `Replay of ${msg.name}, started by ${msg.by} ${to} at ${msg.speed}×: ${msg.state} at ${msg.position_s.toFixed(1)} s, ${msg.frames} frames`;
    if (msg.truncated) text += ' (the recording ends cut short)';
    if (msg.error) text += `: ${msg.error}`;
    this.caption.textContent = text;
    if (msg.state === 'playing') this.section.hidden = false;
  }
}
