// The editor's free-form image surfaces and camera views in headless Chromium: Table 1's image 14
// (a bicubic B-spline image surface, its control net drawn over the image) has a control point
// dragged in the surface's plane and along its normal, the magnification map and the 3D view are
// switched on. Screenshots of each step go to the output folder.
// Usage: node surface.test.mjs ANAMORPH_BINARY SOURCE_DIR OUTPUT_DIR  (77: no Chromium)
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';
import { startServer, launch, waitFor } from './harness.mjs';

const [binary, source, outDir] = process.argv.slice(2);
const chromium = await launch();
if (!chromium) process.exit(77);
fs.mkdirSync(outDir, { recursive: true });
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'anamorph-surface-'));
fs.mkdirSync(path.join(dir, 'paper'));
fs.mkdirSync(path.join(dir, 'models'));
for (const f of ['14.toml', 'world.toml']) fs.copyFileSync(path.join(source, 'examples/paper', f), path.join(dir, 'paper', f));
fs.copyFileSync(path.join(source, 'examples/models/torus_knot.obj'), path.join(dir, 'models/torus_knot.obj'));
const server = await startServer(binary, path.join(dir, 'paper/14.toml'));
const browser = await chromium.browser();
const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));
const shot = (name) => page.screenshot({ path: path.join(outDir, `${name}.png`) });
const value = (k) => page.evaluate((key) => window.anamorphEditor.doc.value(key), k);
const settled = (v) => waitFor(page, `version ${v} shown`, (v0) => {
  const e = window.anamorphEditor;
  const f = e && e.preview.frame;
  return f && f.version >= v0 && e.doc.version >= v0 && !e.doc.inflight && !f.coarse && f.pass === f.passes || null;
}, v);

try {
  await page.goto(server.url);
  await settled(1);
  const nets = await page.evaluate(() => window.anamorphEditor.overlay.nets.nets().map((n) => ({ key: n.key, us: n.us, vs: n.vs })));
  assert.equal(nets.length, 1);
  assert.equal(nets[0].key, 'camera.org');
  // Clamped cubic knots over 4 points: the Greville abscissae are 0, 1/3, 2/3, 1.
  for (const g of [nets[0].us, nets[0].vs]) g.forEach((x, i) => assert.ok(Math.abs(x - i / 3) < 1e-12, `${g}`));
  await shot('01-net');

  // Drag control point (1, 1), drawn at (1/3, 1/3), a third of a cell to the right: it moves
  // along the net's row direction (+x here) by a third of the net's spacing there (2.4 / 3).
  const before = await value('camera.org.points.1.1');
  const box = await page.locator('#overlay').boundingBox();
  const v0 = (await page.evaluate(() => window.anamorphEditor.doc.version));
  const x0 = box.x + box.width / 3, y0 = box.y + box.height / 3;
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  for (let i = 1; i <= 8; ++i) await page.mouse.move(x0 + (i / 8) * box.width / 9, y0);
  await page.mouse.up();
  await waitFor(page, 'the point to move', (b) => {
    const p = window.anamorphEditor.doc.value('camera.org.points.1.1');
    return !window.anamorphEditor.doc.inflight && p && p[0] !== b[0] ? p : null;
  }, before);
  await settled(v0 + 1);
  const after = await value('camera.org.points.1.1');
  assert.ok(Math.abs(after[0] - before[0] - 0.8) < 0.02, `moved ${after[0] - before[0]} along x, expected 0.8`);
  assert.ok(Math.abs(after[1] - before[1]) < 1e-9 && Math.abs(after[2] - before[2]) < 1e-9, `${after} vs ${before}`);
  await shot('02-dragged');

  // Shift-drag upwards: along the surface's normal (here +y or -y), not in its plane.
  const v1 = (await page.evaluate(() => window.anamorphEditor.doc.version));
  await page.keyboard.down('Shift');
  await page.mouse.move(x0, y0);
  await page.mouse.down();
  for (let i = 1; i <= 6; ++i) await page.mouse.move(x0, y0 - (i / 6) * box.height / 12);
  await page.mouse.up();
  await page.keyboard.up('Shift');
  await settled(v1 + 1);
  const lifted = await value('camera.org.points.1.1');
  assert.ok(Math.abs(lifted[1] - after[1]) > 0.1, `the normal moved y: ${lifted} from ${after}`);
  assert.ok(Math.abs(lifted[0] - after[0]) < 1e-6 && Math.abs(lifted[2] - after[2]) < 1e-6, `${lifted} vs ${after}`);

  // The magnification map and the 3D view show something.
  await page.click('#ov-mag');
  await waitFor(page, 'the legend', () => !document.getElementById('legend').hidden || null);
  await page.click('#ov-3d');
  const lit = await waitFor(page, 'the 3D view drawn', () => {
    const c = document.getElementById('overview');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] + d[i + 1] + d[i + 2] > 200) ++n;
    return n > 500 ? n : null;
  });
  assert.ok(lit > 500);
  await shot('03-views');
  assert.deepEqual(errors, [], 'no script errors on the page');
  console.log('surface test passed; screenshots in', outDir);
} finally {
  await browser.close();
  server.stop();
  fs.rmSync(dir, { recursive: true, force: true });
}
