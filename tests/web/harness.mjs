// What the editor's browser tests share: the server started as a user starts it, Chromium
// launched as this machine allows (Debian's binary, no sandbox as root, no background
// networking), and waiting on the page without fixed sleeps.
import { spawn } from 'node:child_process';
import fs from 'node:fs';

export const CHROMIUM = process.env.ANAMORPH_CHROMIUM || '/usr/bin/chromium';
export const FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync', '--disable-quic'];

// {browser()} or null (with the reason printed) when Chromium or playwright-core is missing.
export async function launch() {
  if (!fs.existsSync(CHROMIUM)) {
    console.log(`skipped: no Chromium at ${CHROMIUM} (scripts/install-deps installs it)`);
    return null;
  }
  let pw;
  try {
    pw = await import('playwright-core');
  } catch {
    console.log('skipped: playwright-core is not installed (scripts/test runs `npm ci` in tests/web)');
    return null;
  }
  return { browser: () => pw.chromium.launch({ executablePath: CHROMIUM, args: FLAGS }) };
}

// `anamorph serve SCENE` on a free port with a known token; resolves once it prints its address.
export function startServer(binary, scene, extra = []) {
  const token = 'e2e' + Math.random().toString(16).slice(2);
  const child = spawn(binary, ['serve', scene, '--port', '0', '--token', token, ...extra],
                      { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    let out = '';
    const timer = setTimeout(() => reject(new Error(`no address from anamorph serve: ${out}`)), 60000);
    child.on('exit', (code) => reject(new Error(`anamorph serve exited (${code}): ${out}`)));
    child.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/open (http:\/\/\S+)/);
      if (!m) return;
      clearTimeout(timer);
      resolve({ url: m[1], token, origin: new URL(m[1]).origin, stop: () => child.kill('SIGTERM') });
    });
  });
}

// A checksum of the preview's last frame (its raw pixels).
export function frameSum(page) {
  return page.evaluate(() => {
    const p = window.anamorphEditor.preview.frame.pixels;
    let h = 2166136261;
    for (let i = 0; i < p.length; i += 7) h = Math.imul(h ^ p[i], 16777619);
    return h >>> 0;
  });
}

// Polls `fn(arg)` in the page until it returns something truthy (bounded: 60 s, then an error
// naming what was awaited).
export async function waitFor(page, what, fn, arg) {
  try {
    const h = await page.waitForFunction(fn, arg, { timeout: 60000, polling: 50 });
    return await h.jsonValue();
  } catch (e) {
    throw new Error(`timed out waiting for ${what}: ${e.message.split('\n')[0]}`);
  }
}
