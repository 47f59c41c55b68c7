// End-to-end test of `anamorph serve` in real headless Chromium (Debian's /usr/bin/chromium,
// driven by playwright-core; never `playwright install`). Each step acts as a user would, checks
// what the page and the server then hold, and leaves a screenshot in the output folder.
// Usage: node editor.test.mjs ANAMORPH_BINARY SOURCE_DIR OUTPUT_DIR
// Exits 77 (skipped) when Chromium or playwright-core is missing.
import { spawn, execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';
import { startServer, launch, frameSum, waitFor } from './harness.mjs';

const [binary, source, outDir] = process.argv.slice(2);
const chromium = await launch();
if (!chromium) process.exit(77);
fs.mkdirSync(outDir, { recursive: true });

// The demo scene, copied to a folder of its own (the editor writes there when saving).
const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'anamorph-editor-'));
fs.mkdirSync(path.join(dir, 'models'));
fs.copyFileSync(path.join(source, 'examples/demo.toml'), path.join(dir, 'demo.toml'));
fs.copyFileSync(path.join(source, 'examples/models/torus_knot.obj'), path.join(dir, 'models/torus_knot.obj'));
const server = await startServer(binary, path.join(dir, 'demo.toml'));
const browser = await chromium.browser();
const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
const errors = [];
page.on('pageerror', (e) => errors.push(e.message));

let n = 0;
async function step(name, body) {
  const t0 = Date.now();
  try {
    await body();
  } finally {
    await page.screenshot({ path: path.join(outDir, `${String(++n).padStart(2, '0')}-${name}.png`) });
  }
  console.log(`ok ${n} ${name} (${Date.now() - t0} ms)`);
}
const state = () => page.evaluate(() => window.anamorphEditor.doc.state);
const value = (k) => page.evaluate((key) => window.anamorphEditor.doc.value(key), k);
// The first frame drawn of document version >= v (its pass, whether coarse).
const frameOf = (v, final = false) => waitFor(page, `a frame of version ${v}`, (args) => {
  if (!window.anamorphEditor) return null;
  const f = window.anamorphEditor.preview.frame;
  const d = window.anamorphEditor.doc;
  return f && f.version >= args.v && d.version >= args.v && !d.inflight && (!args.final || (!f.coarse && f.pass === f.passes)) ? { version: f.version, pass: f.pass } : null;
}, { v, final });
// Clicks and waits for the document's next version to reach the page.
async function clickAndWait(selector) {
  const v = (await state()).version;
  await page.click(selector);
  await waitFor(page, `a new version after clicking ${selector}`, (v0) => {
    const d = window.anamorphEditor.doc;
    return d.version > v0 && !d.inflight || null;
  }, v);
}
const run = (args) => execFileSync(binary, args, { encoding: 'utf8' });

try {
  await step('open', async () => {
    await page.goto(server.url);
    await frameOf(1);
    assert.equal(await page.title(), 'anamorph editor');
    assert.ok(!page.url().includes('token='), 'the token stays out of the address bar');
  });

  await step('fov', async () => {
    const before = await frameSum(page);
    const v = (await state()).version;
    await page.fill('[data-key="camera.fov"] input[type=number]', '40');
    await page.press('[data-key="camera.fov"] input[type=number]', 'Enter');
    await frameOf(v + 1);
    assert.equal(await value('camera.fov'), 40);
    const after = await frameSum(page);
    assert.notEqual(after, before, 'the preview changed with the fov');
  });

  await step('orbit', async () => {
    // Navigate: a drag orbits the eye around the point looked at (the distance stays), the wheel
    // dollies (the distance scales by e^-0.1 a notch).
    const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    const from0 = await value('camera.look_from'), at = await value('camera.look_at');
    const box = await page.locator('#overlay').boundingBox();
    const v = (await state()).version;
    await page.mouse.move(box.x + box.width * 0.5, box.y + box.height * 0.5);
    await page.mouse.down();
    for (let i = 1; i <= 5; ++i) await page.mouse.move(box.x + box.width * (0.5 + 0.02 * i), box.y + box.height * 0.5);
    await page.mouse.up();
    await frameOf(v + 1);
    await waitFor(page, 'the drag to end', () => !window.anamorphEditor.doc.inflight || null);
    const from1 = await value('camera.look_from');
    assert.notDeepEqual(from1, from0, 'the eye moved');
    assert.deepEqual(await value('camera.look_at'), at, 'around the point looked at');
    assert.ok(Math.abs(dist(from1, at) - dist(from0, at)) < 1e-4, `distance ${dist(from1, at)} vs ${dist(from0, at)}`);
    const v2 = (await state()).version;
    await page.mouse.wheel(0, -100);
    await frameOf(v2 + 1);
    const from2 = await value('camera.look_from');
    assert.ok(Math.abs(dist(from2, at) / dist(from1, at) - Math.exp(-0.1)) < 1e-5, `dolly ${dist(from2, at) / dist(from1, at)}`);
  });

  await step('fisheye', async () => {
    const v = (await state()).version;
    await page.selectOption('#preset', 'fisheye');
    await frameOf(v + 1);
    assert.equal(await value('camera.preset'), 'fisheye');
    await page.fill('[data-key="camera.fov"] input[type=number]', '180');
    await page.press('[data-key="camera.fov"] input[type=number]', 'Enter');
    await frameOf(v + 2, true);
    const alpha = await page.evaluate(() => {
      const f = window.anamorphEditor.preview.frame;
      const a = (x, y) => f.pixels[(y * f.width + x) * 4 + 3];
      return { corner: a(0, 0), corner2: a(f.width - 1, f.height - 1), center: a(f.width >> 1, f.height >> 1) };
    });
    assert.deepEqual(alpha, { corner: 0, corner2: 0, center: 255 }, 'transparent outside the circle');
  });

  // A coin where the user clicks: on the surface under that pixel, seen through the fisheye.
  const px = 560, py = 330;  // the preview's pixel (960 x 540, the image's own size)
  let clicked, position;
  await step('coin', async () => {
    const before = (await state()).text;
    fs.writeFileSync(path.join(dir, 'before.toml'), before);
    await page.click('[data-tool=coin]');
    const box = await page.locator('#overlay').boundingBox();
    const v = (await state()).version;
    await page.mouse.click(box.x + (px + 0.5) * box.width / 960, box.y + (py + 0.5) * box.height / 540);
    await frameOf(v + 1);
    const coins = await value('camera.coin');
    assert.equal(coins.length, 1, 'one coin');
    position = coins[0].position;
    clicked = await page.evaluate(() => window.anamorphEditor.overlay.lastPick);
    assert.ok(clicked.result.hit, 'the click hit a surface');
    // The page picked at the pixel's center (to within a hundredth of a pixel).
    assert.ok(Math.abs(clicked.u * 960 - (px + 0.5)) < 0.01 && Math.abs(clicked.v * 540 - (py + 0.5)) < 0.01,
              `picked at (${clicked.u * 960}, ${clicked.v * 540}), the pixel's center is (${px + 0.5}, ${py + 0.5})`);
    // The same point as the position AOV of that pixel, rendered apart by the Python module.
    const aov = JSON.parse(execFileSync(path.join(source, 'scripts/python'), [path.join(source, 'tests/web/position_at.py'),
      path.join(dir, 'before.toml'), String(px), String(py)], { encoding: 'utf8' }));
    for (let i = 0; i < 3; ++i)
      assert.ok(Math.abs(aov[i] - position[i]) < 1e-4 * (1 + Math.abs(aov[i])),
                `coin position ${position} against the position AOV ${aov}`);
    // And the camera's inverse map takes it back to the clicked pixel (the coin leaves its own
    // center where it was).
    fs.writeFileSync(path.join(dir, 'with-coin.toml'), (await state()).text);
    const back = JSON.parse(run(['project', path.join(dir, 'with-coin.toml'), '--point', position.join(','),
      '--json'])).pixels;
    assert.ok(back.some(([x, y]) => Math.abs(x - (px + 0.5)) < 0.01 && Math.abs(y - (py + 0.5)) < 0.01),
              `anamorph project gives ${JSON.stringify(back)}, the click was at (${px + 0.5}, ${py + 0.5})`);
  });

  let moved;
  await step('drag', async () => {
    const box = await page.locator('#overlay').boundingBox();
    const at = (x, y) => [box.x + x * box.width / 960, box.y + y * box.height / 540];
    const v = (await state()).version;
    await page.mouse.move(...at(px + 0.5, py + 0.5));
    await page.mouse.down();
    for (let i = 1; i <= 10; ++i) await page.mouse.move(...at(px + 0.5 - 12 * i, py + 0.5 - 4 * i));
    await page.mouse.up();
    await waitFor(page, 'the coin to move', (p0) => {
      const c = window.anamorphEditor.doc.value('camera.coin.0.position');
      return c && c.some((x, i) => x !== p0[i]) ? c : null;
    }, position);
    await frameOf(v + 1);
    moved = await value('camera.coin.0.position');
    assert.notDeepEqual(moved, position);
  });

  await step('undo-redo', async () => {
    // Undo until the coin is back where it was placed (the drag may have made several edits).
    for (let i = 0; i < 20 && JSON.stringify(await value('camera.coin.0.position')) !== JSON.stringify(position); ++i)
      await clickAndWait('#undo');
    assert.deepEqual(await value('camera.coin.0.position'), position, 'undo puts the coin back');
    const v = (await state()).version;
    await page.keyboard.press('Control+Shift+Z');
    await waitFor(page, 'redo by the keyboard', (v0) => window.anamorphEditor.doc.version > v0 || null, v);
    for (let i = 0; i < 20 && JSON.stringify(await value('camera.coin.0.position')) !== JSON.stringify(moved); ++i)
      await clickAndWait('#redo');
    assert.deepEqual(await value('camera.coin.0.position'), moved, 'redo moves it again');
    await frameOf((await state()).version, true);
  });

  await step('keyframe-scrub', async () => {
    await page.click('text=Animate strength from 0');
    await waitFor(page, 'the [[animate]] entry', () => (window.anamorphEditor.doc.value('animate') || []).length === 1 || null);
    const anim = (await value('animate'))[0];
    assert.equal(anim.key, 'camera.coin.0.strength');
    assert.deepEqual(anim.keys, [[0, 0], [48, 0.5]]);
    // The keys show on the timeline as diamonds; clicking one goes to its frame.
    const ticks = await page.$$eval('#ticks .tick', (t) => t.map((b) => Number(b.dataset.frame)));
    assert.deepEqual(ticks, [0, 48], 'a diamond at each keyed frame');
    const strengthAt = async (frame) => {
      await page.fill('#time', String(frame));
      await page.dispatchEvent('#time', 'input');
      await waitFor(page, `frame ${frame}`, (f) => window.anamorphEditor.doc.state.frame === f || null, frame);
      await frameOf((await state()).version, true);
      const sites = await page.evaluate(async () => (await (await fetch(`/api/coins?version=${window.anamorphEditor.doc.version}`)).json()).sites);
      return { m: sites.length ? sites[0].strength : 0, sum: await frameSum(page) };
    };
    const at0 = await strengthAt(0), at24 = await strengthAt(24), at48 = await strengthAt(48);
    assert.equal(at0.m, 0, 'no strength at frame 0 (the coin is dropped)');
    assert.ok(at24.m > 0 && at24.m < 0.5, `strength ${at24.m} at frame 24 lies between the keys`);
    assert.equal(at48.m, 0.5);
    assert.notEqual(at0.sum, at48.sum, 'the image changes along the animation');
  });

  await step('save', async () => {
    await page.click('#save');
    await waitFor(page, 'the saved message', () => document.getElementById('toast').textContent.startsWith('Saved') || null);
    const saved = fs.readFileSync(path.join(dir, 'demo.toml'), 'utf8');
    fs.writeFileSync(path.join(outDir, 'saved.toml'), saved);
    assert.equal(saved, (await state()).text, 'the file holds the document');
    for (const s of [/preset = "fisheye"/, /\[\[camera\.coin\]\]/, /\[\[animate\]\]/])
      assert.match(saved, s, 'the saved file holds the edits');
    // The file's own text stays: every comment line of the demo is still there.
    const original = fs.readFileSync(path.join(source, 'examples/demo.toml'), 'utf8');
    for (const line of original.split('\n').filter((l) => l.startsWith('#')))
      assert.ok(saved.includes(line), `the comment "${line}" was kept`);
    // The saved file is a scene the command line renders.
    run(['render', path.join(dir, 'demo.toml'), '--width', '96', '--height', '54', '-o', path.join(outDir, 'saved.png')]);
  });

  await step('render', async () => {
    // The final render from the page: progress, then the PNG offered for download, at the
    // scene's own size.
    await page.click('#render');
    await page.uncheck('#r-seq');  // (the animation is offered, the scene having keys: one frame here)
    await page.click('#r-start');
    await waitFor(page, 'the final render', () => {
      const t = document.getElementById('r-status').textContent;
      return t.startsWith('done') || t.startsWith('failed') || t.startsWith('cancelled') ? t : null;
    });
    const status = await page.textContent('#r-status');
    assert.match(status, /^done in/, status);
    const href = await page.getAttribute('#r-links a[href*="result.png"]', 'href');
    assert.ok(href, 'a PNG to download');
    const head = await page.evaluate(async (h) => [...new Uint8Array(await (await fetch(h)).arrayBuffer()).slice(0, 24)], href);
    assert.deepEqual(head.slice(1, 4), [80, 78, 71], 'a PNG file');
    const size = (o) => ((head[o] << 24) | (head[o + 1] << 16) | (head[o + 2] << 8) | head[o + 3]) >>> 0;
    const image = (await state()).document.image || {};
    assert.deepEqual([size(16), size(20)], [image.width || 960, image.height || 540], 'the scene\'s size');
  });

  assert.deepEqual(errors, [], 'no script errors on the page');
  console.log(`all ${n} steps passed; screenshots in ${outDir}`);
} finally {
  await browser.close();
  server.stop();
  fs.rmSync(dir, { recursive: true, force: true });
}
