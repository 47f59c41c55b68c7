#!/usr/bin/env node
// The editor's preview, measured in the browser (docs/performance.md, "The editor"): Performance
// API timestamps from the input event to the frame painted (requestAnimationFrame after the
// frame was drawn), in headless Chromium driven by playwright-core (tests/web's).
//   node bench/editor-preview.mjs [build/anamorph] [examples/demo.toml]
// Prints: the latency from a typed fov change to the first frame and to the refined 1-spp frame
// (medians of 20), and the updates per second while a slider is dragged (albedo preview).
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const { startServer, launch } = await import(path.join(root, 'tests/web/harness.mjs'));
const binary = process.argv[2] || path.join(root, 'build/anamorph');
const scene = process.argv[3] || path.join(root, 'examples/demo.toml');
const median = (a) => { const s = [...a].sort((x, y) => x - y); return s[s.length >> 1]; };

const chromium = await launch();
if (!chromium) process.exit(1);
const server = await startServer(binary, scene);
const browser = await chromium.browser();
const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
await page.goto(server.url);
await page.waitForFunction(() => window.anamorphEditor && window.anamorphEditor.preview.frame);
const settle = () => page.waitForFunction(() => {
  const e = window.anamorphEditor, f = e.preview.frame;
  return !e.doc.inflight && f.version === e.doc.version && !f.coarse && f.pass === f.passes;
}, null, { timeout: 120000 });
const api = (p, body) => page.evaluate(async ([p, body]) => (await fetch(p, { method: 'POST', body: JSON.stringify(body) })).json(), [p, body]);

// 1. A typed change: first frame (the coarse one) and the full-size 1-spp frame.
await api('/api/preview', { integrator: 'scene', max_spp: 1 });
await settle();
const first = [], refined = [], kinds = [];
for (let i = 0; i < 20; ++i) {
  const fov = 50 + (i % 2) * 5 + i * 0.1;
  const box = '[data-key="camera.fov"] input[type=number]';
  await page.fill(box, String(fov.toFixed(1)));
  const t = await page.evaluate(() => { window.benchFrames = window.anamorphStats.frames.length; return performance.now(); });
  await page.press(box, 'Enter');
  await settle();
  const r = await page.evaluate(() => ({ lat: window.anamorphStats.latencies.slice(-1)[0],
                                         frames: window.anamorphStats.frames.slice(window.benchFrames) }));
  // The page's own measure (the input event's timestamp to the first frame painted), and from
  // just before the key press to the last frame (the full-size pass) painted.
  first.push(r.lat.ms);
  refined.push(r.frames[r.frames.length - 1].t - t);
  kinds.push(r.frames.map((f) => (f.coarse ? 'c' : 'f')).join(''));
}

// 2. Dragging the fov slider for 3 s with the albedo preview: frames painted per second.
await api('/api/preview', { integrator: 'albedo', max_spp: 1 });
await settle();
const slider = await page.locator('[data-key="camera.fov"] input[type=range]').boundingBox();
await page.mouse.move(slider.x + slider.width * 0.3, slider.y + slider.height / 2);
await page.mouse.down();
const n0 = await page.evaluate(() => window.anamorphStats.frames.length);
const t0 = Date.now();
let k = 0;
while (Date.now() - t0 < 3000) {
  const x = 0.3 + 0.4 * Math.abs(Math.sin(++k / 30));
  await page.mouse.move(slider.x + slider.width * x, slider.y + slider.height / 2);
  await page.waitForTimeout(8);
}
await page.mouse.up();
const drag = await page.evaluate((n0) => {
  const f = window.anamorphStats.frames.slice(n0);
  const versions = new Set(f.map((x) => x.version));
  const span = (f[f.length - 1].t - f[0].t) / 1000;
  return { frames: f.length, versions: versions.size, seconds: span, latencies: window.anamorphStats.latencies.slice(-50).map((l) => l.ms) };
}, n0);

console.log(JSON.stringify({
  first_frame_ms_median: median(first), first_frame_ms: first.map((x) => Math.round(x)),
  refined_1spp_ms_median: median(refined), refined_1spp_ms: refined.map((x) => Math.round(x)),
  frames_per_change: kinds,
  drag_updates_per_second: drag.versions / drag.seconds, drag_frames_per_second: drag.frames / drag.seconds,
  drag_latency_ms_median: median(drag.latencies),
}, null, 1));
await browser.close();
server.stop();
