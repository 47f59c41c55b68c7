// The live preview: frames arrive by long poll and are drawn as they come (a coarse quarter-size
// frame first, then the refining passes). Each frame is timed from the input that asked for it
// to the moment it is painted (Performance API), for docs/performance.md's figures; the
// numbers are in window.anamorphStats.
import { nextFrame } from './api.js';

export class Preview extends EventTarget {
  constructor(canvas, doc) {
    super();
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.doc = doc;
    this.frame = null;  // the last frame drawn (pixels kept for the no-ray overlay and picking)
    this.stats = { latencies: [], frames: [] };
    window.anamorphStats = this.stats;
    this.scratch = document.createElement('canvas');
  }

  async run() {
    let seq = 0;
    for (;;) {
      let f = null;
      try {
        f = await nextFrame(seq);
      } catch (e) {
        this.dispatchEvent(new CustomEvent('lost', { detail: e }));
        await new Promise((r) => setTimeout(r, 1000));
        continue;
      }
      if (!f) continue;
      seq = f.seq;
      this.draw(f);
    }
  }

  draw(f) {
    const s = this.scratch;
    s.width = f.width;
    s.height = f.height;
    s.getContext('2d').putImageData(new ImageData(f.pixels, f.width, f.height), 0, 0);
    // The image canvas keeps the refined size; a coarse frame is scaled up smoothly into it.
    const full = f.coarse ? [f.width * 4, f.height * 4] : [f.width, f.height];
    if (this.canvas.width !== full[0] || this.canvas.height !== full[1]) {
      this.canvas.width = full[0];
      this.canvas.height = full[1];
    }
    this.ctx.imageSmoothingEnabled = true;
    this.ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    this.ctx.drawImage(s, 0, 0, this.canvas.width, this.canvas.height);
    this.frame = f;
    requestAnimationFrame(() => this.painted(f));
    this.dispatchEvent(new CustomEvent('frame', { detail: f }));
  }

  // After the frame reached the screen: latency from each input it answers.
  painted(f) {
    const now = performance.now();
    this.stats.frames.push({ t: now, version: f.version, pass: f.pass, passes: f.passes,
                             coarse: f.coarse, width: f.width, height: f.height,
                             server_seconds: f.seconds });
    const answered = this.doc.inputTimes.filter(([, v]) => v <= f.version);
    this.doc.inputTimes = this.doc.inputTimes.filter(([, v]) => v > f.version);
    for (const [t, v] of answered) this.stats.latencies.push({ ms: now - t, version: v, coarse: f.coarse });
    if (this.stats.frames.length > 2000) this.stats.frames.splice(0, 1000);
  }
}
