// Mouse navigation that fits the camera: for cameras with look_from / look_at (every view preset)
// a drag orbits the eye around the point looked at, shift or the right button pans both, the
// wheel dollies; a dome's tilt follows alt + vertical drag. Other cameras (org/dir compositions)
// move their rig by its transform instead: not by mouse, in the panel.
import { drag } from './drag.js';

const sub = (a, b) => a.map((x, i) => x - b[i]);
const add = (a, b) => a.map((x, i) => x + b[i]);
const mul = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a.reduce((s, x, i) => s + x * b[i], 0);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => mul(a, 1 / Math.hypot(...a));
const round = (a) => a.map((x) => Number(x.toPrecision(7)));

// Rotates v about the unit axis k by angle a (Rodrigues).
function rotate(v, k, a) {
  const c = Math.cos(a), s = Math.sin(a);
  return add(add(mul(v, c), mul(cross(k, v), s)), mul(k, dot(k, v) * (1 - c)));
}

export class Navigator {
  constructor(doc, decl) {
    this.doc = doc;
    this.decl = decl;
  }

  params() {
    const preset = this.doc.value('camera.preset') ?? 'perspective';
    const cam = this.doc.value('camera') || {};
    if (cam.org || cam.dir || cam.gltf_camera !== undefined) return null;
    const info = this.decl.presets[preset];
    return info ? new Set(info.params.map((s) => s.name)) : null;
  }

  view() {
    const p = this.params();
    if (!p || !p.has('look_from') || !p.has('look_at')) return null;
    const spec = (n) => JSON.parse(this.decl.presets[this.doc.value('camera.preset') ?? 'perspective'].params.find((s) => s.name === n).default);
    const v = (n) => this.doc.value(`camera.${n}`) ?? spec(n);
    return { from: v('look_from'), at: v('look_at'), up: p.has('up') ? v('up') : [0, 1, 0], tilt: p.has('tilt') };
  }

  start(e, canvas) {
    const v = this.view();
    if (!v) return;
    const pan = e.shiftKey || e.button === 2, tilt = e.altKey && v.tilt;
    const x0 = e.clientX, y0 = e.clientY;
    const tilt0 = this.doc.value('camera.tilt') ?? 0;
    const move = (m) => {
      const dx = (m.clientX - x0) / canvas.getBoundingClientRect().width;
      const dy = (m.clientY - y0) / canvas.getBoundingClientRect().height;
      if (tilt) {
        const t = Math.max(-90, Math.min(90, tilt0 + dy * 90));
        this.doc.edit([{ key: 'camera.tilt', value: Number(t.toFixed(2)) }], m.timeStamp);
        return;
      }
      const up = norm(v.up);
      const off = sub(v.from, v.at);
      const dist = Math.hypot(...off);
      const right = norm(cross(mul(off, -1), up));
      if (pan) {
        const shift = add(mul(right, -dx * dist), mul(norm(cross(right, mul(off, -1))), dy * dist));
        this.doc.edit([{ key: 'camera.look_from', value: round(add(v.from, shift)) },
                       { key: 'camera.look_at', value: round(add(v.at, shift)) }], m.timeStamp);
        return;
      }
      let o = rotate(off, up, -dx * Math.PI);
      const r2 = norm(cross(mul(o, -1), up));
      const o2 = rotate(o, r2, -dy * Math.PI * 0.5);
      // Stay clear of the poles, where the up vector and the view line up.
      if (Math.abs(dot(norm(o2), up)) < 0.985) o = o2;
      this.doc.edit([{ key: 'camera.look_from', value: round(add(v.at, o)) }], m.timeStamp);
    };
    drag(canvas, e, move);
  }

  dolly(e) {
    const v = this.view();
    if (!v) return;
    const k = Math.exp(Math.sign(e.deltaY) * 0.1);
    this.doc.edit([{ key: 'camera.look_from', value: round(add(v.at, mul(sub(v.from, v.at), k))) }], e.timeStamp);
  }
}
