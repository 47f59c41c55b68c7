// The editor's size handles end to end in headless Chromium (docs/solve.md, "In the editor"): on
// the demo scene, tick the fov free, press on the red sphere with the size tool and drag the
// handle 40 px right, and check through the API that the solved camera shows the handle's segment
// (across the sphere's bounding box) as long as the goal, within the residual the solve
// reported, and that the goal is the segment's starting image length plus the drag.
// Usage: node size.test.mjs ANAMORPH_BINARY SOURCE_DIR OUTPUT_DIR (exits 77 without Chromium or
// playwright-core).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';
import { startServer, launch, waitFor } from './harness.mjs';

const [binary, source, outDir] = process.argv.slice(2);
const chromium = await launch();
if (!chromium) process.exit(77);
fs.mkdirSync(outDir, { recursive: true });

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'anamorph-size-'));
fs.mkdirSync(path.join(dir, 'models'));
fs.copyFileSync(path.join(source, 'examples/demo.toml'), path.join(dir, 'demo.toml'));
fs.copyFileSync(path.join(source, 'examples/models/torus_knot.obj'), path.join(dir, 'models/torus_knot.obj'));
const server = await startServer(binary, path.join(dir, 'demo.toml'));
const browser = await chromium.browser();
const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));
const api = (p, body) => page.evaluate(async ([p, body]) => (await fetch(p, { method: 'POST', body: JSON.stringify(body) })).json(), [p, body]);
// The image length of the segment a-b as a fraction of the 960 x 540 image's width, as the
// camera of `version` shows it (the image position of each end nearest to `near`).
async function shownLength(a, b, version) {
  const ends = [];
  for (const position of [a, b]) {
    const r = await api('/api/project', { position, version });
    assert.ok(r.uv.length > 0, `the camera of version ${version} sees ${position}`);
    ends.push(r.uv[0]);
  }
  return Math.hypot((ends[0][0] - ends[1][0]) * 960, (ends[0][1] - ends[1][1]) * 540) / 960;
}

try {
  await page.goto(server.url);
  await waitFor(page, 'the first frame', () => window.anamorphEditor && window.anamorphEditor.preview.frame || null);
  await page.check('[data-key="camera.fov"] input.free');
  await page.click('[data-tool=size]');
  const box = await page.locator('#overlay').boundingBox();
  const at = (x, y) => [box.x + x * box.width / 960, box.y + y * box.height / 540];
  const v0 = await page.evaluate(() => window.anamorphEditor.doc.version);
  // The red sphere (radius 0.8 about [1.6, 0.8, 0.6], at pixel 690, 284 of the demo's 960 x 540):
  // a press on it, dragged 40 px right in 8 moves.
  await page.mouse.move(...at(690, 284));
  await page.mouse.down();
  // The handles are up once the press's pick has answered; the image length they start from, as
  // the server's camera shows it (the drag has not asked for a solve yet).
  const start = await waitFor(page, 'the size handles', () => { const s = window.anamorphEditor.pins.sizes[0]; return s ? { from: s.from, to: s.to } : null; });
  const before = await shownLength(start.from, start.to, v0);
  for (let i = 1; i <= 8; ++i) await page.mouse.move(...at(690 + 5 * i, 284));
  await page.mouse.up();
  const last = await waitFor(page, 'the last solve', () => {
    const e = window.anamorphEditor, p = e.pins;
    return !p.busy && p.queued === null && p.last && e.doc.version === p.last.version ? p.last : null;
  });
  assert.ok(last.version > v0, 'the solve made a new version');
  const size = await page.evaluate(() => { const s = window.anamorphEditor.pins.sizes[0]; return { from: s.from, to: s.to, fraction: s.fraction }; });
  // The segment runs across the sphere's bounding box through its centre.
  const mid = size.from.map((x, i) => (x + size.to[i]) / 2);
  assert.ok(Math.hypot(mid[0] - 1.6, mid[1] - 0.8, mid[2] - 0.6) < 1e-9, `the segment's middle ${mid} is the sphere's centre`);
  assert.ok(Math.abs(Math.hypot(...size.from.map((x, i) => x - size.to[i])) - 1.6) < 1e-9, 'the segment is the sphere\'s diameter');
  // The goal: the starting image length plus the 40 px dragged (the segment nearly horizontal).
  assert.ok(Math.abs(size.fraction * 960 - (before * 960 + 40)) < 1, `goal ${size.fraction * 960} px, started at ${before * 960} px, dragged 40 px`);
  const c = last.constraints[0];
  assert.equal(c.kind, 'size');
  assert.ok(last.met && c.residual < 0.5, `met: residual ${c.residual} %`);
  const fov = last.values.find((v) => v.name === 'camera.fov');
  assert.ok(fov.value < 55, `zoomed in: the demo's fov 55 -> ${fov.value}`);
  // The server's camera of that version shows the segment that long, within the residual.
  const after = await shownLength(size.from, size.to, last.version);
  const off = 100 * Math.abs(after / size.fraction - 1);
  assert.ok(off <= c.residual + 1e-6, `shown ${after * 960} px for a goal of ${size.fraction * 960} px: ${off} % off, reported ${c.residual} %`);
  await page.screenshot({ path: path.join(outDir, 'size.png') });
  assert.deepEqual(errors, []);
  console.log(`ok size handle: ${before * 960} -> ${after * 960} px (goal ${size.fraction * 960}), fov 55 -> ${fov.value}, residual ${c.residual.toExponential(2)} %, re-projected ${off.toExponential(2)} %; solve ${last.ms.toFixed(1)} ms`);
} finally {
  await browser.close();
  server.stop();
  fs.rmSync(dir, { recursive: true, force: true });
}
