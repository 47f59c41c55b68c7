// The timeline: the frame shown (the scene's [[animate]] keys evaluated there, by the server),
// keyframes set from any numeric field at the current frame, and playback as a low-resolution
// loop. Keys live in the document's [[animate]] entries, as a scene file writes them.
import { post } from './api.js';

export class Timeline {
  constructor(doc, els, hooks) {
    Object.assign(this, { doc, els, hooks });
    this.frame = 0;
    this.playing = false;
    els.time.addEventListener('input', () => this.go(Number(els.time.value)));
    els.end.addEventListener('change', () => { els.time.max = els.end.value; this.drawTicks(this.entries()); });
    els.play.addEventListener('click', () => (this.playing ? this.stop() : this.play()));
  }

  entries() { return this.doc.value('animate') || []; }
  animated(key) { return this.entries().some((a) => a.key === key); }

  update() {
    const keys = this.entries();
    const last = Math.max(0, ...keys.flatMap((a) => a.keys.map((k) => k[0])));
    if (last > Number(this.els.end.value)) { this.els.end.value = last; this.els.time.max = last; }
    this.drawTicks(keys);
    this.els.keys.textContent = keys.length ? `${keys.length} animated key${keys.length > 1 ? 's' : ''}: ${keys.map((a) => a.key).join(', ')}` : 'no keyframes: ◆ beside a field keys it at this frame';
    this.frame = this.doc.state.frame;
    this.els.time.value = this.frame;
    this.els.label.textContent = `frame ${this.frame}`;
  }

  // A diamond over the slider at every keyed frame, naming its keys; clicking it goes there.
  drawTicks(entries) {
    const at = new Map();
    for (const a of entries) for (const [f] of a.keys) at.set(f, [...(at.get(f) || []), a.key]);
    const max = Number(this.els.time.max) || 1;
    this.els.ticks.replaceChildren(...[...at].filter(([f]) => f >= 0 && f <= max).map(([f, names]) => {
      const b = document.createElement('button');
      b.textContent = '◆';
      b.className = 'tick';
      b.dataset.frame = f;
      b.style.left = `${(100 * f) / max}%`;
      b.title = `frame ${f}: ${names.join(', ')}`;
      b.addEventListener('click', () => { this.els.time.value = f; this.go(f); });
      return b;
    }));
  }

  async go(frame) {
    this.els.label.textContent = `frame ${frame}`;
    await this.doc.action('/api/time', { frame });
  }

  // A key at the current frame for `key` with `value` (its [[animate]] entry made when new).
  keyframe(key, value) {
    const list = this.entries();
    const i = list.findIndex((a) => a.key === key);
    const f = this.frame;
    if (i < 0) {
      this.doc.edit([{ key: 'animate', value: [...list, { key, keys: [[f, value]], interpolation: 'smooth' }] }]);
      return;
    }
    const keys = list[i].keys.filter((k) => k[0] !== f).concat([[f, value]]).sort((a, b) => a[0] - b[0]);
    this.doc.edit([{ key: `animate.${i}.keys`, value: keys }]);
  }

  // The paper's animation: a coin's strength from 0 at the first frame to its value at the last.
  animateFromZero(key, value) {
    const end = Number(this.els.end.value) || 48;
    const list = this.entries().filter((a) => a.key !== key);
    this.doc.edit([{ key: 'animate', value: [...list, { key, keys: [[0, 0], [end, value]], interpolation: 'smooth' }] }]);
    this.hooks.toast(`${key} now grows from 0 at frame 0 to ${value} at frame ${end}: press ▶ to play it.`);
  }

  async play() {
    this.playing = true;
    this.els.play.textContent = '❚❚';
    const before = await post('/api/preview', {});
    await post('/api/preview', { max_width: 320, max_height: 180, max_spp: 1 });
    const end = Number(this.els.end.value);
    let f = this.frame;
    while (this.playing) {
      f = f >= end ? 0 : f + 1;
      this.els.time.value = f;
      await this.go(f);
      await this.hooks.frameShown(this.doc.version);
    }
    await post('/api/preview', { max_width: before.max_width, max_height: before.max_height, max_spp: before.max_spp });
  }

  stop() {
    this.playing = false;
    this.els.play.textContent = '▶';
  }
}
