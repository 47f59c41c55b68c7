// A small 3D view of the camera itself, the paper's Figure 3 for the user's own camera: the image
// surface (the rays' origins over the image), a sparse set of its rays, each drawn until it meets
// one of the scene's objects' bounding boxes, the free-form surface's control net, and those
// boxes. Drag to turn it, the wheel zooms. Data: GET /api/rays (the camera shown) and the document (the net).
import { get } from './api.js';
import { drag } from './drag.js';

const sub = (a, b) => a.map((x, i) => x - b[i]);
const add = (a, b) => a.map((x, i) => x + b[i]);
const mul = (a, s) => a.map((x) => x * s);

// Where the ray o + t d first enters box [lo, hi] (t > 0), or Infinity.
function hitBox(o, d, [lo, hi]) {
  let t0 = 0, t1 = Infinity;
  for (let k = 0; k < 3; ++k) {
    if (Math.abs(d[k]) < 1e-12) { if (o[k] < lo[k] || o[k] > hi[k]) return Infinity; continue; }
    let a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
    if (a > b) [a, b] = [b, a];
    t0 = Math.max(t0, a);
    t1 = Math.min(t1, b);
    if (t0 > t1) return Infinity;
  }
  return t0 > 1e-9 ? t0 : Infinity;
}

export class Overview {
  constructor(canvas, doc, nets) {
    Object.assign(this, { canvas, doc, nets });
    this.ctx = canvas.getContext('2d');
    this.yaw = 0.7;
    this.pitch = 0.45;
    this.data = null;
    this.zoom = 1;
    canvas.addEventListener('pointerdown', (e) => this.turn(e));
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.zoom = Math.max(0.2, Math.min(20, this.zoom * Math.exp(-Math.sign(e.deltaY) * 0.15)));
      this.draw();
    }, { passive: false });
  }

  async refresh(version) {
    if (this.canvas.hidden) return;
    try {
      this.data = await get(`/api/rays?nu=24&nv=14&version=${version}`);
    } catch { return; }
    this.draw();
  }

  turn(down) {
    const yaw0 = this.yaw, pitch0 = this.pitch;
    drag(this.canvas, down, (e) => {
      this.yaw = yaw0 + (e.clientX - down.clientX) * 0.01;
      this.pitch = Math.max(-1.5, Math.min(1.5, pitch0 + (e.clientY - down.clientY) * 0.01));
      this.draw();
    });
  }

  draw() {
    const { ctx, canvas, data } = this;
    const W = canvas.width, H = canvas.height;
    ctx.fillStyle = '#101216';
    ctx.fillRect(0, 0, W, H);
    if (!data) return;
    const orgs = data.org.filter(Boolean);
    const pts = [...orgs, ...data.boxes.flat()];
    if (!pts.length) return;
    const lo = [0, 1, 2].map((k) => Math.min(...pts.map((p) => p[k])));
    const hi = [0, 1, 2].map((k) => Math.max(...pts.map((p) => p[k])));
    const center = mul(add(lo, hi), 0.5);
    const size = Math.max(1e-6, Math.hypot(...sub(hi, lo)));
    const cy = Math.cos(this.yaw), sy = Math.sin(this.yaw), cp = Math.cos(this.pitch), sp = Math.sin(this.pitch);
    const scale = 0.85 * this.zoom * Math.min(W, H) / size;
    const proj = (p) => {
      const q = sub(p, center);
      const x = cy * q[0] - sy * q[2], z = sy * q[0] + cy * q[2];
      const y = cp * q[1] - sp * z;
      return [W / 2 + x * scale, H / 2 - y * scale];
    };
    const line = (a, b, color, width = 1) => {
      ctx.strokeStyle = color;
      ctx.lineWidth = width;
      ctx.beginPath();
      ctx.moveTo(...proj(a));
      ctx.lineTo(...proj(b));
      ctx.stroke();
    };
    for (const [l, h] of data.boxes) {
      const c = (i) => [i & 1 ? h[0] : l[0], i & 2 ? h[1] : l[1], i & 4 ? h[2] : l[2]];
      for (const [a, b] of [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]])
        line(c(a), c(b), '#59606e');
    }
    const { nu, nv } = data;
    const at = (i, j) => data.org[j * nu + i];
    const dirAt = (i, j) => data.dir[j * nu + i];
    // Rays: every third one, to the first box they enter (or a scene's size).
    for (let j = 1; j < nv; j += 3)
      for (let i = 1; i < nu; i += 3) {
        const o = at(i, j), d = dirAt(i, j);
        if (!o) continue;
        const t = Math.min(size, ...data.boxes.map((b) => hitBox(o, d, b)));
        line(o, add(o, mul(d, t)), '#f0a63a70');
      }
    // The image surface: the origins' grid.
    for (let j = 0; j < nv; ++j)
      for (let i = 0; i < nu; ++i) {
        if (i + 1 < nu && at(i, j) && at(i + 1, j)) line(at(i, j), at(i + 1, j), '#4fb3d9', 1.2);
        if (j + 1 < nv && at(i, j) && at(i, j + 1)) line(at(i, j), at(i, j + 1), '#4fb3d9', 1.2);
      }
    for (const net of this.nets.nets()) {
      const P = net.points;
      for (let i = 0; i < P.length; ++i)
        for (let j = 0; j < P[i].length; ++j) {
          if (j + 1 < P[i].length) line(P[i][j], P[i][j + 1], '#7fe0a0', 1);
          if (i + 1 < P.length) line(P[i][j], P[i + 1][j], '#7fe0a0', 1);
        }
    }
    ctx.fillStyle = '#8a93a5';
    ctx.font = '11px system-ui, sans-serif';
    ctx.fillText('image surface · rays · objects\u2019 boxes · net', 8, H - 8);
  }
}
