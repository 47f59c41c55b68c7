#!/usr/bin/env node
// The editor's pin tool, measured in the browser as the preview is (bench/editor-preview.mjs,
// docs/performance.md): on the demo scene with a coin, look_at and fov ticked free, a pin dragged
// back and forth for 4 s (a mouse move every 8 ms), alone and beside two fixed pins. Prints, per
// case, the server's solve time (/api/solve's "ms") and the latency from the pointer event
// (event.timeStamp) to the first frame of the solved version painted (requestAnimationFrame after
// drawing: window.anamorphStats), medians and 90th percentiles, and updates per second.
//   node bench/editor-pin.mjs [build/anamorph] [albedo|scene]
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const { startServer, launch } = await import(path.join(root, 'tests/web/harness.mjs'));
const binary = process.argv[2] || path.join(root, 'build/anamorph');
const integrator = process.argv[3] || 'scene';
const q = (a, p) => { const s = [...a].sort((x, y) => x - y); return s[Math.min(s.length - 1, Math.floor(p * s.length))]; };

const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'anamorph-pin-bench-'));
fs.mkdirSync(path.join(dir, 'models'));
fs.writeFileSync(path.join(dir, 'demo.toml'), fs.readFileSync(path.join(root, 'examples/demo.toml'), 'utf8') +
  '\n[[camera.coin]]\nposition = [1.6, 0.8, 0.6]\nstrength = 0.4\nradius = 0.15\n');
fs.copyFileSync(path.join(root, 'examples/models/torus_knot.obj'), path.join(dir, 'models/torus_knot.obj'));
const chromium = await launch();
if (!chromium) process.exit(1);
const server = await startServer(binary, path.join(dir, 'demo.toml'));
const browser = await chromium.browser();
const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
await page.goto(server.url);
await page.waitForFunction(() => window.anamorphEditor && window.anamorphEditor.preview.frame);
await page.evaluate(async (i) => fetch('/api/preview', { method: 'POST', body: JSON.stringify({ integrator: i }) }), integrator);
await page.check('[data-key="camera.look_at"] input.free');
await page.check('[data-key="camera.fov"] input.free');
await page.click('[data-tool=pin]');
const box = await page.locator('#overlay').boundingBox();
const at = (x, y) => [box.x + x * box.width / 960, box.y + y * box.height / 540];
const idle = () => page.waitForFunction(() => { const p = window.anamorphEditor.pins; return !p.busy && p.queued === null; });

// Drags from image pixel (x, y) for 4 s; the stats of the solves answered meanwhile.
async function dragFor(x, y) {
  const n0 = await page.evaluate(() => { window.benchSolves = []; const p = window.anamorphEditor.pins;
    if (!p.wrapped) { const send = p.send.bind(p); p.send = async (t) => { await send(t); if (p.last) window.benchSolves.push([p.last.ms, p.last.iterations]); }; p.wrapped = true; }
    return window.anamorphStats.latencies.length; });
  await page.mouse.move(...at(x, y));
  await page.mouse.down();
  const t0 = Date.now();
  for (let k = 0; Date.now() - t0 < 4000; ++k) {
    await page.mouse.move(...at(x + 30 * Math.sin(k / 40), y + 15 * Math.sin(k / 25)));
    await page.waitForTimeout(8);
  }
  await page.mouse.up();
  await idle();
  await page.waitForTimeout(500);
  const r = await page.evaluate((n) => ({ solves: window.benchSolves, lat: window.anamorphStats.latencies.slice(n).map((l) => l.ms) }), n0);
  const ms = r.solves.map((x) => x[0]);
  return { solves: r.solves.length, updates_per_second: r.solves.length / 4,
           solve_ms_median: q(ms, 0.5), solve_ms_p90: q(ms, 0.9),
           iterations_median: q(r.solves.map((x) => x[1]), 0.5),
           latency_ms_median: q(r.lat, 0.5), latency_ms_p90: q(r.lat, 0.9), latencies: r.lat.length };
}

const one = await dragFor(480, 258);  // the mirror sphere
// Two more pins held where they are (the glass and the red sphere's centres), then the first
// dragged again.
for (const [x, y] of [[270, 284], [690, 284]]) {
  await page.mouse.move(...at(x, y)); await page.mouse.down(); await page.mouse.move(...at(x + 1, y)); await page.mouse.up(); await idle();
}
const three = await dragFor(480 + 30 * Math.sin(0), 258);
console.log(JSON.stringify({ integrator, one_pin: one, three_pins: three }, null, 1));
await browser.close();
server.stop();
fs.rmSync(dir, { recursive: true, force: true });
