// The pin tool (docs/solve.md, "In the editor"): drag any point of the image to where it should
// be, and the server solves the camera for every pin (POST /api/solve, the library behind
// `anamorph solve`), changing only the keys ticked free in the panels. Each pin is a world point
// (the surface under the cursor where the drag began) and the image position it should have;
// the solved values become the document's next version, so the preview shows them and undo
// takes them back. One solve is on its way at a time: moves made meanwhile are merged into the
// next.
import { post } from './api.js';

export class Pins {
  constructor(doc, hooks) {
    this.doc = doc;
    this.hooks = hooks;  // {problem(message), changed()}
    this.list = [];      // {point: [x, y, z], uv: [u, v], residual: px | null}
    // Size handles: a world segment across an object (`from`, `to`) whose image length should be
    // `fraction` of the image's width; `ends` its image positions as last shown or dragged.
    this.sizes = [];     // {from, to, ends: [[u, v], [u, v]], fraction, residual: % | null}
    this.free = new Set();  // dotted camera keys the solve may change
    this.busy = false;
    this.queued = null;  // the input time of a solve asked for while one was on its way
    this.last = null;    // the last answer (what the browser tests read)
  }

  isFree(key) { return this.free.has(key); }
  setFree(key, on) {
    if (on) this.free.add(key); else this.free.delete(key);
    this.hooks.changed();
  }

  add(point, uv) {
    this.list.push({ point, uv, residual: null });
    return this.list.length - 1;
  }

  remove(i) {
    this.list.splice(i, 1);
    this.hooks.changed();
  }

  // A size handle over the segment from-to shown at `ends`; `aspect` the image's width / height.
  addSize(from, to, ends, aspect) {
    const s = { from, to, ends, fraction: 0, residual: null };
    this.sizes.push(s);
    this.setEnd(s, 1, ends[1], aspect);
    return s;
  }

  // Moves end k of size handle s to `uv`: the goal becomes the length between its ends.
  setEnd(s, k, uv, aspect) {
    s.ends[k] = uv;
    const [a, b] = s.ends;
    s.fraction = Math.max(1e-4, Math.hypot(a[0] - b[0], (a[1] - b[1]) / aspect));
  }

  // The size handle end within `px` CSS pixels of (u, v): {size, end}, or null.
  nearSize(u, v, w, h, px = 9) {
    for (const s of this.sizes)
      for (const k of [0, 1])
        if (Math.hypot((s.ends[k][0] - u) * w, (s.ends[k][1] - v) * h) < px) return { size: s, end: k };
    return null;
  }

  // After a drag: the size handles' ends where the solved camera shows them (their goals kept).
  async showSizes(version) {
    for (const z of this.sizes) {
      const seen = await Promise.all([z.from, z.to].map((position) =>
        post('/api/project', { position, version }).then((a) => a.uv, () => [])));
      seen.forEach((uvs, k) => {
        if (!uvs.length) return;
        const near = (q) => Math.hypot(q[0] - z.ends[k][0], q[1] - z.ends[k][1]);
        z.ends[k] = uvs.reduce((a, b) => (near(b) < near(a) ? b : a));
      });
    }
    this.hooks.changed();
  }

  removeSize(s) {
    this.sizes.splice(this.sizes.indexOf(s), 1);
    this.hooks.changed();
  }

  // The pin whose target is within `px` CSS pixels of (u, v) in a w x h view, or -1.
  near(u, v, w, h, px = 9) {
    return this.list.findIndex((p) => Math.hypot((p.uv[0] - u) * w, (p.uv[1] - v) * h) < px);
  }

  // Solves for the pins as they are now (or after the solve on its way). While dragging, a few
  // iterations from the last solution (the next move goes on from there); `final` (the drag
  // ended): until the solver stops.
  request(inputTime, final = false) {
    this.final = this.final || final;
    if (this.busy || this.doc.inflight) { this.queued = inputTime; return; }
    this.send(inputTime);
  }

  async send(inputTime) {
    const iterations = this.final ? 100 : 8;
    this.final = false;
    if (!this.free.size) {
      this.hooks.problem('Tick the camera keys the pins may change (the box beside a value in the panels).');
      return;
    }
    this.busy = true;
    try {
      const r = await post('/api/solve', {
        version: this.doc.version, apply: true, iterations, free: [...this.free],
        constraints: this.list.map((p) => ({ kind: 'pin', point: p.point, uv: p.uv })).concat(
          this.sizes.map((s) => ({ kind: 'size', from: s.from, to: s.to, fraction: s.fraction }))),
      });
      const n = this.list.length;
      r.constraints.forEach((c, i) => {
        const g = i < n ? this.list[i] : this.sizes[i - n];
        if (g) g.residual = c.residual;
      });
      this.last = r;
      this.doc.inputTimes.push([inputTime, r.version]);
      this.doc.adopt(r.state);
      if (iterations > 8) this.showSizes(r.version);
    } catch (e) {
      this.hooks.problem(e.message);
      if (e.status === 409) await this.doc.reload();
    } finally {
      this.busy = false;
      this.hooks.changed();
      if (this.queued !== null) {
        const t = this.queued;
        this.queued = null;
        this.request(t);
      }
    }
  }

  // Targets as crosshairs with their residuals; size handles as a bar between two squares.
  draw(ctx, W, H, s) {
    this.drawSizes(ctx, W, H, s);
    ctx.font = `${12 * s}px system-ui, sans-serif`;
    this.list.forEach((p, i) => {
      const x = p.uv[0] * W, y = p.uv[1] * H;
      ctx.lineWidth = 2 * s;
      ctx.strokeStyle = '#000';
      ctx.fillStyle = '#5fd35f';
      ctx.beginPath();
      ctx.arc(x, y, 5 * s, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
      const label = `pin ${i}` + (p.residual === null ? '' : ` · ${p.residual < 0.01 ? p.residual.toExponential(1) : p.residual.toFixed(2)} px`);
      ctx.fillStyle = '#000a';
      ctx.fillRect(x + 8 * s, y + 4 * s, ctx.measureText(label).width + 8 * s, 17 * s);
      ctx.fillStyle = '#fff';
      ctx.fillText(label, x + 12 * s, y + 17 * s);
    });
  }

  drawSizes(ctx, W, H, s) {
    ctx.font = `${12 * s}px system-ui, sans-serif`;
    this.sizes.forEach((z, i) => {
      const [a, b] = z.ends.map((e) => [e[0] * W, e[1] * H]);
      ctx.lineWidth = 2 * s;
      ctx.strokeStyle = '#ffd23f';
      ctx.beginPath();
      ctx.moveTo(...a);
      ctx.lineTo(...b);
      ctx.stroke();
      ctx.fillStyle = '#ffd23f';
      ctx.strokeStyle = '#000';
      for (const [x, y] of [a, b]) {
        ctx.fillRect(x - 5 * s, y - 5 * s, 10 * s, 10 * s);
        ctx.strokeRect(x - 5 * s, y - 5 * s, 10 * s, 10 * s);
      }
      const label = `size ${i} · ${(100 * z.fraction).toFixed(1)} % of the width` +
        (z.residual === null ? '' : ` · off ${z.residual < 0.01 ? z.residual.toExponential(1) : z.residual.toFixed(2)} %`);
      const tw = ctx.measureText(label).width + 8 * s;  // (above the bar's middle, inside the image)
      const x = Math.min(Math.max(0, (a[0] + b[0]) / 2 - tw / 2), W - tw);
      const y = Math.max(17 * s, Math.min(a[1], b[1]) - 10 * s);
      ctx.fillStyle = '#000a';
      ctx.fillRect(x, y - 13 * s, tw, 17 * s);
      ctx.fillStyle = '#fff';
      ctx.fillText(label, x + 4 * s, y);
    });
  }
}
