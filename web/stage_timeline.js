// The mission's progress as a timeline of its stages (telemetry's "timeline", built by the server
// from the flight software's stages): each stage with the time it started, how long it has run and
// what the drone waits for now ("waiting for scale: 2/3 pairs", "holding 4.2 s of 10 s at 0.8 m"),
// the stages still to come, and the mission's result once it ends.
const clock = (unixS) => new Date(unixS * 1000).toLocaleTimeString();
const duration = (s) => (s < 60 ? `${s.toFixed(1)} s` : `${Math.floor(s / 60)} min ${Math.round(s % 60)} s`);

export class StageTimelineView {
  constructor(list, title) {
    this.list = list;    // <ol>
    this.title = title;  // a caption: mission, start, state
    this.key = '';
  }

  // `timeline` as the server sends it (null: no mission has run yet), `now` the telemetry's time.
  render(timeline, now) {
    if (!timeline) {
      this.title.textContent = 'no mission yet';
      this.list.replaceChildren();
      this.key = '';
      return;
    }
    const running = timeline.ended === null;
    const total = (running ? now : timeline.ended) - timeline.started;
    this.title.textContent = `${timeline.mission}, started ${clock(timeline.started)}, ` +
        (running ? `running for ${duration(total)}` : `ended after ${duration(total)}`);
    // Rebuild the rows when a stage begins or ends; otherwise only their words and durations change.
    const key = `${timeline.started}|${timeline.stages.length}|${timeline.ended}`;
    if (key !== this.key) this.rebuild(timeline);
    this.key = key;
    const rows = this.list.children;
    timeline.stages.forEach((s, i) => {
      const row = rows[i + (timeline.dropped > 0 ? 1 : 0)];
      const ran = (s.ended === null ? now : s.ended) - s.started;
      row.querySelector('.stage-time').textContent = `${clock(s.started)} · ${duration(Math.max(0, ran))}${s.ended === null ? ' so far' : ''}`;
      row.querySelector('.stage-wait').textContent = s.waiting_for || '';
    });
  }

  rebuild(timeline) {
    const rows = [];
    const row = (cls, name) => {
      const li = document.createElement('li');
      li.className = cls;
      const n = document.createElement('b'); n.textContent = name;
      const t = document.createElement('span'); t.className = 'stage-time';
      const w = document.createElement('span'); w.className = 'stage-wait';
      li.append(n, ' ', t, ' ', w);
      return li;
    };
    if (timeline.dropped > 0) {
      const li = document.createElement('li'); li.className = 'stage-dropped';
      li.textContent = `… ${timeline.dropped} earlier stages`;
      rows.push(li);
    }
    const last = timeline.stages.length - 1;
    timeline.stages.forEach((s, i) => {
      const state = s.ended !== null ? 'stage-done' : 'stage-current';
      rows.push(row(i === last && timeline.ended === null ? 'stage-current' : state, `${s.index ? s.index + ' ' : ''}${s.name}`));
    });
    const lastIndex = last >= 0 ? timeline.stages[last].index : 0;
    if (timeline.ended === null) {
      for (let k = lastIndex + 1; k <= timeline.stage_count; ++k) {
        const li = document.createElement('li'); li.className = 'stage-next'; li.textContent = `${k} …`;
        rows.push(li);
      }
    } else {
      const li = document.createElement('li');
      li.className = timeline.succeeded ? 'stage-result ok' : 'stage-result failed';
      li.textContent = (timeline.succeeded ? '✔ ' : '✘ ') + (timeline.result || 'ended');
      rows.push(li);
    }
    this.list.replaceChildren(...rows);
  }
}
