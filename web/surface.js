// Free-form image surfaces (Bezier, B-spline, NURBS origin functions, or the surface a
// `from_surface` direction is made from) shaped by hand: each control point is drawn at the
// image position it governs most (its Greville abscissa: the average of the knots its basis
// function spans, mapped through u_range / v_range), joined into the control net. Dragging a
// point moves it in the surface's plane there (one net spacing in the image moves it to its
// neighbour's position); shift-dragging up and down moves it along the surface normal.
const FREE_FORM = new Set(['bezier', 'bspline', 'nurbs']);
const sub = (a, b) => a.map((x, i) => x - b[i]);
const add = (a, b) => a.map((x, i) => x + b[i]);
const mul = (a, s) => a.map((x) => x * s);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => mul(a, 1 / (Math.hypot(...a) || 1));

// Greville abscissae of n control points, as fractions of the image (0..1).
function greville(f, n, axis) {
  const range = f[`${axis}_range`] || [0, 1];
  let g;
  if (f.type === 'bezier' || n < 2) {
    g = Array.from({ length: n }, (_, j) => (n > 1 ? j / (n - 1) : 0.5));
  } else {
    const p = Math.min(f[`degree_${axis}`] ?? 3, n - 1);
    let k = f[`knots_${axis}`];
    if (!k) {
      const clamped = (f[`knot_type_${axis}`] ?? 'clamped') === 'clamped';
      k = clamped
        ? [...Array(p + 1).fill(0), ...Array.from({ length: n - p - 1 }, (_, i) => (i + 1) / (n - p)), ...Array(p + 1).fill(1)]
        : Array.from({ length: n + p + 1 }, (_, i) => i / (n + p));
    }
    const lo = k[p], hi = k[n];
    g = Array.from({ length: n }, (_, j) => {
      let s = 0;
      for (let i = j + 1; i <= j + p; ++i) s += k[i];
      return (s / p - lo) / (hi - lo || 1);
    });
  }
  return g.map((x) => (x - range[0]) / (range[1] - range[0] || 1));
}

export class SurfaceNets {
  constructor(doc) { this.doc = doc; }

  // The free-form surfaces of the camera: [{key, points, us, vs}].
  nets() {
    const out = [];
    for (const key of ['camera.org', 'camera.dir.surface']) {
      const f = this.doc.value(key);
      if (!f || !FREE_FORM.has(f.type) || !Array.isArray(f.points) || !f.points.length) continue;
      const rows = f.points;
      out.push({ key, points: rows, us: greville(f, rows[0].length, 'u'), vs: greville(f, rows.length, 'v') });
    }
    return out;
  }

  draw(ctx, W, H, s) {
    for (const net of this.nets()) {
      ctx.strokeStyle = '#7fe0a0b0';
      ctx.lineWidth = 1.5 * s;
      const at = (i, j) => [net.us[j] * W, net.vs[i] * H];
      for (let i = 0; i < net.points.length; ++i) {
        ctx.beginPath();
        for (let j = 0; j < net.points[i].length; ++j) ctx[j ? 'lineTo' : 'moveTo'](...at(i, j));
        ctx.stroke();
      }
      for (let j = 0; j < net.points[0].length; ++j) {
        ctx.beginPath();
        for (let i = 0; i < net.points.length; ++i) ctx[i ? 'lineTo' : 'moveTo'](...at(i, j));
        ctx.stroke();
      }
      for (let i = 0; i < net.points.length; ++i)
        for (let j = 0; j < net.points[i].length; ++j) {
          const [x, y] = at(i, j);
          ctx.fillStyle = '#7fe0a0';
          ctx.strokeStyle = '#000';
          ctx.fillRect(x - 5 * s, y - 5 * s, 10 * s, 10 * s);
          ctx.strokeRect(x - 5 * s, y - 5 * s, 10 * s, 10 * s);
        }
    }
  }

  // The control point under the cursor (within 9 CSS pixels): {net, i, j} or null.
  hit(u, v, rect) {
    for (const net of this.nets())
      for (let i = 0; i < net.points.length; ++i)
        for (let j = 0; j < net.points[i].length; ++j)
          if (Math.hypot((u - net.us[j]) * rect.width, (v - net.vs[i]) * rect.height) < 9) return { net, i, j };
    return null;
  }

  // The point's displacement for an image motion (du, dv): the net's local spacing decides the
  // scale, so a drag across one cell moves the point about one cell in space.
  moved(h, du, dv, alongNormal) {
    const P = h.net.points, { i, j, net } = h;
    const row = P[i], n = row.length, m = P.length;
    const j0 = Math.max(0, j - 1), j1 = Math.min(n - 1, j + 1);
    const i0 = Math.max(0, i - 1), i1 = Math.min(m - 1, i + 1);
    const tu = mul(sub(row[j1], row[j0]), 1 / ((net.us[j1] - net.us[j0]) || 1));
    const tv = mul(sub(P[i1][j], P[i0][j]), 1 / ((net.vs[i1] - net.vs[i0]) || 1));
    const p = row[j];
    if (alongNormal) {
      const nrm = unit(cross(tu, tv));
      return add(p, mul(nrm, -dv * Math.hypot(...tv)));
    }
    return add(p, add(mul(tu, du), mul(tv, dv)));
  }
}
