// What is drawn over the preview (coins with their (uc, vc) and radius, the region where the
// camera has no ray, the magnification map) and what the mouse does there: navigate the view, or
// place, move and shape coins through the camera's own rays (the server picks the surface under
// the cursor with the distorted camera as it is).
import { get, post } from './api.js';
import { SurfaceNets } from './surface.js';
import { drag } from './drag.js';

const RAMP = [[40, 90, 200], [120, 170, 230], [235, 235, 235], [245, 170, 70], [215, 50, 40]];

function ramp(t) {  // t in [0, 1]
  const x = Math.max(0, Math.min(1, t)) * (RAMP.length - 1);
  const i = Math.min(RAMP.length - 2, Math.floor(x)), f = x - i;
  return RAMP[i].map((c, k) => Math.round(c + (RAMP[i + 1][k] - c) * f));
}

export class Overlay {
  constructor(canvas, legend, doc, preview, hooks) {
    Object.assign(this, { canvas, legend, doc, preview, hooks });
    this.ctx = canvas.getContext('2d');
    this.sites = [];
    this.show = { coins: true, rays: true, mag: false, net: true };
    this.nets = new SurfaceNets(doc);
    this.pins = null;  // the pin tool's pins (pins.js), set by the page
    this.tool = 'navigate';
    this.selected = -1;
    this.mag = null;       // {w, h, data: Float32Array, version}
    this.raysLayer = null; // a canvas of the no-ray region of the last frame
    this.bind();
  }

  // ---- state from the server ----
  async refresh(version) {
    try {
      this.sites = (await get(`/api/coins?version=${version}`)).sites;
    } catch { this.sites = []; }
    if (this.show.mag) await this.fetchMagnification(version);
    this.draw();
  }

  async fetchMagnification(version) {
    const f = this.preview.frame;
    const w = Math.max(1, Math.round((f ? f.width * (f.coarse ? 4 : 1) : 960) / 4));
    const h = Math.max(1, Math.round((f ? f.height * (f.coarse ? 4 : 1) : 540) / 4));
    const r = await fetch(`/api/magnification?width=${w}&height=${h}&version=${version}`);
    if (!r.ok) return;
    this.mag = { w, h, data: new Float32Array(await r.arrayBuffer()), version };
    this.magLayer = this.magCanvas();
  }

  magCanvas() {
    const { w, h, data } = this.mag;
    const c = document.createElement('canvas');
    c.width = w; c.height = h;
    const img = c.getContext('2d').createImageData(w, h);
    for (let i = 0; i < w * h; ++i) {
      const m = data[i];
      if (!Number.isFinite(m)) continue;
      const [r, g, b] = ramp((Math.log2(m) + 2) / 4);
      img.data.set([r, g, b, 150], i * 4);
    }
    c.getContext('2d').putImageData(img, 0, 0);
    const against = this.sites.length ? 'against the camera without coins' : 'against the mean over the image';
    this.legend.innerHTML = `<div>magnification (linear, ${against})</div>` +
      '<div class="ramp"></div><div class="ticks"><span>¼×</span><span>½×</span><span>1×</span><span>2×</span><span>4×</span></div>';
    this.legend.querySelector('.ramp').style.background =
      `linear-gradient(to right, ${RAMP.map((c) => `rgb(${c})`).join(', ')})`;
    return c;
  }

  onFrame(f) {
    this.raysLayer = this.noRayCanvas(f);
    if (this.canvas.width !== this.preview.canvas.width || this.canvas.height !== this.preview.canvas.height) {
      this.canvas.width = this.preview.canvas.width;
      this.canvas.height = this.preview.canvas.height;
    }
    this.draw();
  }

  // Pixels without a ray tinted, and the border of the region drawn: a fisheye's circle, a
  // panorama's unused corners, wherever a camera gives no ray.
  noRayCanvas(f) {
    const { width: w, height: h, pixels } = f;
    let any = false;
    for (let i = 3; i < pixels.length; i += 4) if (pixels[i] === 0) { any = true; break; }
    if (!any) return null;
    const c = document.createElement('canvas');
    c.width = w; c.height = h;
    const img = c.getContext('2d').createImageData(w, h);
    const none = (x, y) => x >= 0 && y >= 0 && x < w && y < h && pixels[(y * w + x) * 4 + 3] === 0;
    for (let y = 0; y < h; ++y)
      for (let x = 0; x < w; ++x) {
        if (!none(x, y)) continue;
        const edge = !none(x - 1, y) && x > 0 || !none(x + 1, y) && x < w - 1 ||
                     !none(x, y - 1) && y > 0 || !none(x, y + 1) && y < h - 1;
        img.data.set(edge ? [240, 166, 58, 255] : (((x + y) >> 3) & 1 ? [79, 179, 217, 40] : [0, 0, 0, 0]), (y * w + x) * 4);
      }
    c.getContext('2d').putImageData(img, 0, 0);
    return c;
  }

  // ---- drawing ----
  draw() {
    const { ctx, canvas } = this;
    const W = canvas.width, H = canvas.height;
    ctx.clearRect(0, 0, W, H);
    this.legend.hidden = !(this.show.mag && this.magLayer);
    if (this.show.mag && this.magLayer) {
      ctx.imageSmoothingEnabled = true;
      ctx.drawImage(this.magLayer, 0, 0, W, H);
    }
    if (this.show.rays && this.raysLayer) {
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(this.raysLayer, 0, 0, W, H);
    }
    const s = W / canvas.getBoundingClientRect().width || 1;  // canvas pixels per CSS pixel
    if (this.show.net) this.nets.draw(ctx, W, H, s);
    if (this.pins) this.pins.draw(ctx, W, H, s);
    if (!this.show.coins) return;
    for (const site of this.sites) {
      const x = site.uv[0] * W, y = site.uv[1] * H;
      const sel = site.coin === this.selected;
      ctx.lineWidth = 2 * s;
      ctx.strokeStyle = sel ? '#f0a63a' : '#ffffffcc';
      ctx.setLineDash([6 * s, 4 * s]);
      ctx.beginPath();
      ctx.ellipse(x, y, site.radius * W, site.radius * H, 0, 0, 2 * Math.PI);
      ctx.stroke();
      ctx.setLineDash([]);
      ctx.fillStyle = sel ? '#f0a63a' : '#ffffff';
      ctx.strokeStyle = '#000';
      ctx.beginPath();
      ctx.arc(x, y, 6 * s, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
      ctx.font = `${12 * s}px system-ui, sans-serif`;
      const label = `coin ${site.coin}  (${site.uv[0].toFixed(3)}, ${site.uv[1].toFixed(3)})  m ${site.strength.toFixed(2)}  s ${site.stiffness.toFixed(2)}`;
      ctx.fillStyle = '#000a';
      const tw = ctx.measureText(label).width;
      ctx.fillRect(x + 10 * s, y - 22 * s, tw + 8 * s, 17 * s);
      ctx.fillStyle = '#fff';
      ctx.fillText(label, x + 14 * s, y - 9 * s);
    }
  }

  // ---- the mouse ----
  uv(e) {
    const r = this.canvas.getBoundingClientRect();
    return [(e.clientX - r.left) / r.width, (e.clientY - r.top) / r.height];
  }

  // The coin part under the cursor: {coin, part: 'center' | 'ring'} or null.
  hit(e) {
    const r = this.canvas.getBoundingClientRect();
    const [u, v] = this.uv(e);
    for (const site of this.sites) {
      const dx = (u - site.uv[0]) * r.width, dy = (v - site.uv[1]) * r.height;
      if (Math.hypot(dx, dy) < 10) return { coin: site.coin, part: 'center', site };
      const ex = (u - site.uv[0]) / site.radius, ey = (v - site.uv[1]) / site.radius;
      const d = Math.hypot(ex, ey);
      if (Math.abs(d - 1) * site.radius * Math.min(r.width, r.height) < 7) return { coin: site.coin, part: 'ring', site };
    }
    return null;
  }

  setTool(tool) {
    this.tool = tool;
    this.canvas.classList.toggle('coin-tool', tool === 'coin' || tool === 'pin' || tool === 'size');
  }

  bind() {
    const c = this.canvas;
    c.addEventListener('contextmenu', (e) => e.preventDefault());
    c.addEventListener('pointerdown', (e) => this.down(e));
    c.addEventListener('wheel', (e) => this.wheel(e), { passive: false });
  }

  async pick(u, v) {
    try {
      return await post('/api/pick', { u, v, version: this.doc.version });
    } catch (err) {
      this.hooks.problem(err.message);
      return null;
    }
  }

  down(e) {
    if (this.tool === 'pin') { this.pinDown(e); return; }
    if (this.tool === 'size') { this.sizeDown(e); return; }
    if (this.show.net && e.button === 0) {
      const [u, v] = this.uv(e);
      const n = this.nets.hit(u, v, this.canvas.getBoundingClientRect());
      if (n) { this.dragNet(e, n); return; }
    }
    const h = this.show.coins ? this.hit(e) : null;
    if (this.tool === 'coin' || (h && e.button === 0)) {
      if (h) this.dragCoin(e, h);
      else if (e.button === 0) this.addCoin(e);
      return;
    }
    this.hooks.navigate(e, this.canvas);
  }

  // The pin tool: a drag from a pin's target moves it; from anywhere else it pins the surface
  // under the cursor there and drags it; a right click on a pin removes it. Every move asks for
  // a solve (pins.js merges the moves made while one is on its way).
  async pinDown(e) {
    const r = this.canvas.getBoundingClientRect();
    const [u, v] = this.uv(e);
    let i = this.pins.near(u, v, r.width, r.height);
    if (e.button === 2) {
      if (i >= 0) { this.pins.remove(i); this.draw(); }
      return;
    }
    if (e.button !== 0) return;
    let moved = null, ended = null;
    let handle = (m) => { moved = m; };
    let end = (m) => { ended = m; };
    drag(this.canvas, e, (m) => handle(m), (m) => end(m));
    if (i < 0) {  // (the drag is captured before the pick answers: no move is lost meanwhile)
      const p = await this.pick(u, v);
      this.lastPick = { u, v, result: p };
      if (!p || !p.hit) { handle = end = () => {}; this.hooks.problem('No surface under the cursor: a pin needs a point of the scene.'); return; }
      i = this.pins.add(p.position, [u, v]);
    }
    const pin = this.pins.list[i];
    handle = (m) => { pin.uv = this.uv(m); this.draw(); this.pins.request(m.timeStamp); };
    end = (m) => { pin.uv = this.uv(m); this.draw(); this.pins.request(m.timeStamp, true); };
    if (moved) handle(moved);
    if (ended) end(ended);
    this.draw();
  }

  // The size tool: a press on an object puts size handles across it (a segment through its
  // bounding box's centre, along the horizontal box axis that looks longest); dragging a handle
  // (or, at once, the new one's right end) sets the segment's image length as a `size` goal, solved
  // with the pins as they are dragged. A right click on a handle removes it.
  async sizeDown(e) {
    const r = this.canvas.getBoundingClientRect();
    const aspect = r.width / r.height;
    const [u, v] = this.uv(e);
    let h = this.pins.nearSize(u, v, r.width, r.height);
    if (e.button === 2) {
      if (h) { this.pins.removeSize(h.size); this.draw(); }
      return;
    }
    if (e.button !== 0) return;
    let moved = null, ended = null;
    let handle = (m) => { moved = m; };
    let end = (m) => { ended = m; };
    drag(this.canvas, e, (m) => handle(m), (m) => end(m));
    if (!h) {
      const p = await this.pick(u, v);
      const span = p && p.hit && p.box ? await this.objectSpan(p.box) : null;
      if (!span) { handle = end = () => {}; this.hooks.problem('No object under the cursor: size handles go across an object the camera sees.'); return; }
      h = { size: this.pins.addSize(span.from, span.to, span.ends, aspect), end: 1 };
    }
    const z = h.size, k = h.end, start = z.ends[k];
    const to = (m) => { const [mu, mv] = this.uv(m); return [start[0] + mu - u, start[1] + mv - v]; };
    handle = (m) => { this.pins.setEnd(z, k, to(m), aspect); this.draw(); this.pins.request(m.timeStamp); };
    end = (m) => { this.pins.setEnd(z, k, to(m), aspect); this.draw(); this.pins.request(m.timeStamp, true); };
    if (moved) handle(moved);
    if (ended) end(ended);
    this.draw();
  }

  // The segment across a world box that the camera shows longest, of the box's x and z axes
  // through its centre: {from, to, ends (image positions, left end first)} or null (not seen).
  async objectSpan(box) {
    const [lo, hi] = box;
    const c = lo.map((x, i) => (x + hi[i]) / 2);
    let best = null;
    for (const axis of [0, 2]) {
      const from = c.slice(), to = c.slice();
      from[axis] = lo[axis];
      to[axis] = hi[axis];
      const seen = await Promise.all([from, to].map((position) =>
        post('/api/project', { position, version: this.doc.version }).then((a) => a.uv[0] || null, () => null)));
      if (!seen[0] || !seen[1]) continue;
      const len = Math.hypot(seen[0][0] - seen[1][0], seen[0][1] - seen[1][1]);
      if (len > 0 && (!best || len > best.len)) {
        const flip = seen[0][0] > seen[1][0];
        best = { len, from: flip ? to : from, to: flip ? from : to, ends: flip ? [seen[1], seen[0]] : seen };
      }
    }
    return best;
  }

  // Drags a control point of a free-form image surface (surface.js says how it moves).
  dragNet(down, h) {
    const [u0, v0] = this.uv(down);
    const key = `${h.net.key}.points.${h.i}.${h.j}`;
    drag(this.canvas, down, (e) => {
      const [u, v] = this.uv(e);
      const p = this.nets.moved(h, u - u0, v - v0, e.shiftKey);
      this.doc.edit([{ key, value: p.map((x) => Number(x.toPrecision(7))) }], e.timeStamp);
    });
  }

  async addCoin(e) {
    const [u, v] = this.uv(e);
    const t = e.timeStamp;
    const p = await this.pick(u, v);
    this.lastPick = { u, v, result: p };  // (what the browser tests compare)
    if (!p) return;
    if (!p.hit) { this.hooks.problem(p.ray ? 'No surface under the cursor: a coin needs a point of the scene.' : 'The camera has no ray there.'); return; }
    const coins = [...(this.doc.value('camera.coin') || [])];
    coins.push({ position: p.position.map((x) => Number(x.toPrecision(9))), strength: 0.5, radius: 0.2 });
    this.selected = coins.length - 1;
    this.hooks.selectCoin(this.selected);
    this.doc.edit([{ key: 'camera.coin', value: coins }], t);
  }

  dragCoin(down, h) {
    this.selected = h.coin;
    this.hooks.selectCoin(h.coin);
    let busy = false, last = null;
    const move = async (e) => {
      const [u, v] = this.uv(e);
      if (h.part === 'ring') {
        const r = Math.min(2, Math.max(0.01, Math.hypot(u - h.site.uv[0], v - h.site.uv[1])));
        h.site.radius = r;
        this.draw();
        this.doc.edit([{ key: `camera.coin.${h.coin}.radius`, value: Number(r.toFixed(4)) }], e.timeStamp);
        return;
      }
      h.site.uv = [u, v];
      this.draw();
      last = [u, v, e.timeStamp];
      if (busy) return;
      busy = true;
      while (last) {
        const [lu, lv, t] = last;
        last = null;
        const p = await this.pick(lu, lv);
        if (p && p.hit)
          this.doc.edit([{ key: `camera.coin.${h.coin}.position`, value: p.position.map((x) => Number(x.toPrecision(9))) }], t);
      }
      busy = false;
    };
    drag(this.canvas, down, move);
  }

  wheel(e) {
    const h = this.show.coins ? this.hit(e) : null;
    e.preventDefault();
    if (!h) { this.hooks.dolly(e); return; }
    const key = `camera.coin.${h.coin}`;
    if (e.shiftKey) {
      const s = Math.max(0.05, h.site.stiffness * (e.deltaY < 0 ? 1.15 : 1 / 1.15));
      this.doc.edit([{ key: `${key}.stiffness`, value: Number(s.toFixed(3)) }], e.timeStamp);
    } else {
      const m = Math.max(-0.95, Math.min(0.95, h.site.strength + (e.deltaY < 0 ? 0.05 : -0.05)));
      this.doc.edit([{ key: `${key}.strength`, value: Number(m.toFixed(3)) }], e.timeStamp);
    }
  }
}
