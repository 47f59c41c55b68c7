// The editor page: wires the document, the live preview, the overlays, the panels and the
// timeline together. See docs/editor.md.
import { get, post } from './api.js';
import { Doc } from './document.js';
import { Preview } from './preview.js';
import { Overlay } from './overlay.js';
import { Panels } from './panels.js';
import { Navigator } from './navigate.js';
import { Timeline } from './timeline.js';
import { Overview } from './overview.js';
import { Pins } from './pins.js';

const $ = (id) => document.getElementById(id);

function toast(message, bad = false) {
  const t = $('toast');
  t.textContent = message;
  t.className = bad ? 'bad' : '';
  t.hidden = false;
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => (t.hidden = true), bad ? 7000 : 3500);
}

async function main() {
  const decl = await get('/api/declarations');
  const doc = new Doc();
  await doc.reload();
  const preview = new Preview($('image'), doc);
  const nav = new Navigator(doc, decl);
  let selectedCoin = -1;
  const waiting = [];  // [version, resolve] of frameShown()
  const timeline = new Timeline(doc, { time: $('time'), end: $('time-end'), play: $('play'), label: $('time-label'), keys: $('keys'), ticks: $('ticks') },
                                { toast, frameShown: (v) => new Promise((r) => waiting.push([v, r])) });
  const pins = new Pins(doc, { problem: (m) => toast(m, true), changed: () => overlay.draw() });
  const hooks = {
    free: (k) => pins.isFree(k),
    setFree: (k, on) => pins.setFree(k, on),
    keyframe: (k, v) => timeline.keyframe(k, v),
    animated: (k) => timeline.animated(k),
    animateFromZero: (k, v) => timeline.animateFromZero(k, v),
    selectCoin: (i) => { selectedCoin = i; overlay.selected = i; overlay.draw(); panels.render(); },
    selectedCoin: () => selectedCoin,
    problem: (m) => toast(m, true),
    navigate: (e, c) => nav.start(e, c),
    dolly: (e) => nav.dolly(e),
  };
  const overlay = new Overlay($('overlay'), $('legend'), doc, preview, hooks);
  overlay.pins = pins;
  const panels = new Panels($('panels'), decl, doc, hooks);
  const overview = new Overview($('overview'), doc, overlay.nets);
  window.anamorphEditor = { doc, preview, overlay, panels, timeline, overview, pins };

  const refresh = () => {
    $('scene-name').textContent = `${doc.state.file} · v${doc.version}`;
    $('undo').disabled = !doc.state.can_undo;
    $('redo').disabled = !doc.state.can_redo;
    panels.render();
    timeline.update();
  };
  doc.addEventListener('change', refresh);
  doc.addEventListener('problem', (e) => {
    if (!panels.showError(e.detail.key, e.detail.message)) toast(e.detail.message, true);
    else toast(`${e.detail.key}: ${e.detail.message}`, true);
  });
  doc.addEventListener('edited', (e) => { for (const w of e.detail.warnings || []) toast('⚠ ' + w); });
  refresh();

  // Frames: status line, overlays, and another tab's edits (a newer version) reloaded.
  let overlayVersion = 0;
  const recent = [];
  preview.addEventListener('frame', (e) => {
    const f = e.detail;
    overlay.onFrame(f);
    if (f.version > doc.version && !doc.inflight) doc.reload();
    if (f.version !== overlayVersion) {
      overlayVersion = f.version;
      overlay.refresh(f.version);
      overview.refresh(f.version);
    }
    const now = performance.now();
    recent.push(now);
    while (recent.length && recent[0] < now - 1000) recent.shift();
    $('st-frame').textContent = f.coarse ? `${f.width}×${f.height} first look` :
      `${f.width}×${f.height} · pass ${f.pass} of ${f.passes}`;
    $('st-speed').textContent = `${recent.length} frames/s · ${(f.seconds * 1000).toFixed(0)} ms since the change`;
    for (let i = waiting.length - 1; i >= 0; --i)
      if (f.version >= waiting[i][0]) { waiting[i][1](); waiting.splice(i, 1); }
  });
  preview.addEventListener('lost', () => { $('st-msg').textContent = 'server not reachable…'; $('st-msg').className = 'bad'; });
  preview.run();

  // The bar.
  $('undo').onclick = () => doc.action('/api/undo');
  $('redo').onclick = () => doc.action('/api/redo');
  for (const b of document.querySelectorAll('#tools button'))
    b.onclick = () => {
      for (const o of document.querySelectorAll('#tools button')) o.classList.toggle('on', o === b);
      overlay.setTool(b.dataset.tool);
    };
  $('pins-clear').onclick = () => { pins.list.length = 0; pins.sizes.length = 0; overlay.draw(); };
  $('ov-coins').onchange = (e) => { overlay.show.coins = e.target.checked; overlay.draw(); };
  $('ov-rays').onchange = (e) => { overlay.show.rays = e.target.checked; overlay.draw(); };
  $('ov-mag').onchange = async (e) => {
    overlay.show.mag = e.target.checked;
    if (overlay.show.mag) await overlay.fetchMagnification(doc.version);
    overlay.draw();
  };
  $('ov-net').onchange = (e) => { overlay.show.net = e.target.checked; overlay.draw(); };
  $('ov-3d').onchange = (e) => { $('overview').hidden = !e.target.checked; overview.refresh(doc.version); };
  $('preview-integrator').onchange = (e) => post('/api/preview', { integrator: e.target.value });
  $('preview-denoise').onchange = (e) => post('/api/preview', { denoise: e.target.checked });
  $('save').onclick = async () => {
    const r = await doc.action('/api/save', {});
    if (r) toast(`Saved ${r.saved}` + (r.normalized ? ' (written whole: its comments and layout could not be kept, see docs/editor.md)' : ', its comments and layout kept'));
  };
  document.addEventListener('keydown', (e) => {
    if (!(e.ctrlKey || e.metaKey) || e.target.tagName === 'TEXTAREA' || e.target.tagName === 'INPUT') return;
    if (e.key === 'z' || e.key === 'Z') { e.preventDefault(); doc.action(e.shiftKey ? '/api/redo' : '/api/undo'); }
    if (e.key === 's') { e.preventDefault(); $('save').click(); }
  });
  renderDialog();
}

// The final render: progress and ETA while it runs, the files to download when done.
function renderDialog() {
  const d = $('render-dialog');
  // One box per file format the server writes (its sinks), the first ticked.
  get('/api/render').then((s) => {
    $('r-formats').replaceChildren(...s.available.map((f, i) => {
      const l = document.createElement('label');
      const box = document.createElement('input');
      Object.assign(box, { type: 'checkbox', value: f.name, checked: i === 0, id: `r-${f.name}` });
      l.append(box, ` ${f.label || f.name} `);
      return l;
    }));
  });
  $('render').onclick = () => {
    $('r-last').value = $('time-end').value;
    $('r-seq').checked = !!(window.anamorphEditor.doc.value('animate') || []).length;
    d.showModal();
  };
  $('r-close').onclick = () => d.close();
  $('r-cancel').onclick = () => post('/api/render/cancel').catch((e) => ($('r-status').textContent = e.message));
  $('r-start').onclick = async () => {
    try {
      const body = { formats: [...$('r-formats').querySelectorAll('input:checked')].map((b) => b.value) };
      if ($('r-seq').checked) body.frames = [Number($('r-first').value), Number($('r-last').value)];
      await post('/api/render', body);
    } catch (e) { $('r-status').textContent = e.message; return; }
    $('r-links').textContent = '';
    const poll = async () => {
      const s = await get('/api/render');
      $('r-bar').style.width = `${(s.fraction * 100).toFixed(1)}%`;
      const frames = s.frames ? ` · frame ${Math.min(s.frames[1], s.frames[0] + s.frames_done)} of ${s.frames[0]}–${s.frames[1]}` : '';
      $('r-cancel').hidden = s.state !== 'running';
      $('r-start').disabled = s.state === 'running';
      if (s.state === 'running') {
        $('r-status').textContent = `${(s.fraction * 100).toFixed(1)} %${frames} · ${s.seconds.toFixed(1)} s` +
          (s.eta > 0 ? ` · about ${s.eta.toFixed(0)} s to go` : '');
        setTimeout(poll, 300);
      } else if (s.state === 'done') {
        $('r-status').textContent = `done in ${s.seconds.toFixed(1)} s (scene version ${s.version}); the files are in ${s.folder}`;
        $('r-links').replaceChildren('Download: ');
        const link = (ext, f) => {
          const a = document.createElement('a');
          a.href = `/api/render/result.${ext}` + (f === undefined ? '' : `?frame=${f}`);
          a.download = '';
          a.textContent = f === undefined ? ext.toUpperCase() : `${f}`;
          return a;
        };
        for (const ext of s.available.filter((f) => s.formats.includes(f.name)).map((f) => f.extension)) {
          if (!s.frames) { $('r-links').append(link(ext), ' '); continue; }
          $('r-links').append(`${ext.toUpperCase()} frames `);
          for (let f = s.frames[0]; f <= s.frames[1] && f < s.frames[0] + 50; ++f) $('r-links').append(link(ext, f), ' ');
        }
      } else if (s.state === 'cancelled') {
        $('r-status').textContent = `cancelled after ${s.seconds.toFixed(1)} s` + (s.frames ? ` (${s.frames_done} frames finished, in ${s.folder})` : '');
      } else {
        $('r-status').textContent = `failed: ${s.error}`;
      }
    };
    poll();
  };
}

main().catch((e) => toast(`The editor could not start: ${e.message}`, true));
