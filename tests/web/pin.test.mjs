// The editor's pin tool end to end in headless Chromium (docs/solve.md, "In the editor"): on the
// demo scene with a coin, tick the camera keys free in the panels, drag a point of the image with
// the pin tool, and check through the API that the solved camera shows the pinned point at the
// pin's target within the residual the solve reported; the save keeps the file's comments.
// Usage: node pin.test.mjs ANAMORPH_BINARY SOURCE_DIR OUTPUT_DIR (exits 77 without Chromium or
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

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'anamorph-pin-'));
fs.mkdirSync(path.join(dir, 'models'));
const demo = fs.readFileSync(path.join(source, 'examples/demo.toml'), 'utf8') +
  '\n# a coin on the red sphere\n[[camera.coin]]\nposition = [1.6, 0.8, 0.6]\nstrength = 0.4\nradius = 0.15\n';
fs.writeFileSync(path.join(dir, 'demo.toml'), demo);
fs.copyFileSync(path.join(source, 'examples/models/torus_knot.obj'), path.join(dir, 'models/torus_knot.obj'));
const server = await startServer(binary, path.join(dir, 'demo.toml'));
const browser = await chromium.browser();
const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));
const api = (p, body) => page.evaluate(async ([p, body]) => (await fetch(p, { method: 'POST', body: JSON.stringify(body) })).json(), [p, body]);

try {
  await page.goto(server.url);
  await waitFor(page, 'the first frame', () => window.anamorphEditor && window.anamorphEditor.preview.frame || null);
  // The ticks come from the declarations: every number and vector of the camera has one.
  await page.check('[data-key="camera.look_at"] input.free');
  await page.check('[data-key="camera.fov"] input.free');
  assert.deepEqual(await page.evaluate(() => [...window.anamorphEditor.pins.free].sort()), ['camera.fov', 'camera.look_at']);
  assert.ok(await page.locator('[data-key="camera.coin.0.strength"] input.free').count() === 1, 'coins have ticks too');

  await page.click('[data-tool=pin]');
  const box = await page.locator('#overlay').boundingBox();
  const at = (x, y) => [box.x + x * box.width / 960, box.y + y * box.height / 540];
  const v0 = await page.evaluate(() => window.anamorphEditor.doc.version);
  // The mirror sphere's centre (pixel 480, 258 of the demo's 960 x 540) dragged 40 px right,
  // 20 px down.
  await page.mouse.move(...at(480, 258));
  await page.mouse.down();
  for (let i = 1; i <= 8; ++i) await page.mouse.move(...at(480 + 5 * i, 258 + 2.5 * i));
  await page.mouse.up();
  const last = await waitFor(page, 'the last solve', () => {
    const e = window.anamorphEditor, p = e.pins;
    return !p.busy && p.queued === null && p.last && e.doc.version === p.last.version ? p.last : null;
  });
  assert.ok(last.version > v0, 'the solve made a new version');
  const pin = await page.evaluate(() => window.anamorphEditor.pins.list[0]);
  const target = [pin.uv[0] * 960, pin.uv[1] * 540];
  assert.ok(Math.hypot(target[0] - 520, target[1] - 278) < 1, `the pin's target ${target} is where the drag ended`);
  const residual = last.constraints[0].residual;
  assert.ok(last.met && residual < 0.5, `met: residual ${residual} px`);
  // The server's camera of that version shows the pinned point there, within the residual.
  const shown = await api('/api/project', { position: pin.point, version: last.version });
  const px = Math.min(...shown.uv.map((uv) => Math.hypot(uv[0] * 960 - target[0], uv[1] * 540 - target[1])));
  assert.ok(px <= residual + 1e-6, `re-projected ${px} px from the target, reported ${residual}`);
  const lat = await page.evaluate(() => window.anamorphStats.latencies.map((l) => l.ms));
  console.log(`ok pin drag: ${last.values.map((v) => `${v.name} ${v.start.toFixed(4)} -> ${v.value.toFixed(4)}`).join(', ')}; residual ${residual.toExponential(2)} px, re-projected ${px.toExponential(2)} px; solve ${last.ms.toFixed(1)} ms; input-to-frame latencies (ms) ${lat.map((x) => x.toFixed(0)).join(' ')}`);
  await page.screenshot({ path: path.join(outDir, 'pin.png') });

  // Saved with the document's save: the solved values, the file's comments kept, no goals written.
  await page.click('#save');
  await waitFor(page, 'the save', (f) => !document.getElementById('toast').hidden && document.getElementById('toast').textContent.includes('Saved') || null);
  const saved = fs.readFileSync(path.join(dir, 'demo.toml'), 'utf8');
  assert.ok(saved.includes('# a coin on the red sphere') && saved.includes('# The bundled demo'), 'comments kept');
  assert.ok(!saved.includes('constraint'), 'the pins are not written');
  assert.notEqual(saved.match(/^look_at = .*$/m)[0], 'look_at = [0.0, 0.8, 0.0]', 'the solved look_at written');
  assert.deepEqual(errors, []);
  console.log('ok pin test');
} finally {
  await browser.close();
  server.stop();
  fs.rmSync(dir, { recursive: true, force: true });
}
