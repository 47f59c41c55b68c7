// One control per declared key, built from its declaration alone (type, default, range, unit,
// choices, doc): a key added in C++ appears here with no code of the page's. Numbers get a slider
// when their range is bounded and typed entry always (dragging the label scrubs an unbounded
// one); vectors get one box per component; lists, grids, tables and textures are edited as TOML.

import { drag } from './drag.js';

// A declaration's default (TOML text) as a value, or undefined.
export function defaultOf(spec) {
  if (spec.default === null || spec.default === undefined) return undefined;
  const t = spec.default.trim();
  if (t === 'true' || t === 'false') return t === 'true';
  try { return JSON.parse(t.replace(/'/g, '"')); } catch { return t; }
}

// A JSON value as TOML text (inline tables for objects).
export function tomlText(v) {
  if (Array.isArray(v)) return '[' + v.map(tomlText).join(', ') + ']';
  if (v !== null && typeof v === 'object')
    return '{ ' + Object.entries(v).map(([k, e]) => `${/^[A-Za-z0-9_-]+$/.test(k) ? k : JSON.stringify(k)} = ${tomlText(e)}`).join(', ') + ' }';
  return JSON.stringify(v);
}

function rangeText(s) {
  if (s.min === null && s.max === null) return '';
  const lo = s.min === null ? '−∞' : s.min, hi = s.max === null ? '∞' : s.max;
  return ` ${s.min_exclusive ? '(' : '['}${lo}, ${hi}${s.max_exclusive ? ')' : ']'}`;
}

function el(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  Object.assign(e, props);
  for (const c of children) e.append(c);
  return e;
}

// A number input and, for a bounded range, a slider; `send(value)` on change.
function numberControl(spec, value, send) {
  const integer = spec.type === 'integer';
  const box = el('input', { type: 'number', value: value ?? '', step: integer ? 1 : 'any' });
  if (spec.min !== null) box.min = spec.min;
  if (spec.max !== null) box.max = spec.max;
  const parts = [];
  let slider = null;
  const bounded = spec.min !== null && spec.max !== null && spec.max - spec.min <= 1e5;
  if (bounded) {
    slider = el('input', { type: 'range', min: spec.min, max: spec.max,
                                 step: integer ? 1 : (spec.max - spec.min) / 1000, value: value ?? spec.min });
    slider.addEventListener('input', (e) => {
      let x = Number(slider.value);
      if (spec.min_exclusive && x <= spec.min) x = spec.min + (spec.max - spec.min) * 1e-4;
      if (spec.max_exclusive && x >= spec.max) x = spec.max - (spec.max - spec.min) * 1e-4;
      x = integer ? Math.round(x) : Number(x.toPrecision(6));
      box.value = x;
      send(x, e.timeStamp);
    });
    parts.push(slider);
  }
  box.addEventListener('change', (e) => {
    if (box.value === '') return;
    send(integer ? Math.round(Number(box.value)) : Number(box.value), e.timeStamp);
  });
  parts.push(box);
  if (spec.unit) parts.push(el('span', { className: 'unit', textContent: spec.unit.replace('degrees', '°') }));
  const set = (v) => {
    box.value = v ?? '';
    if (slider && v !== undefined) slider.value = v;
  };
  return { parts, box, set };
}

function vectorControl(spec, value, send) {
  const n = spec.type === '[a, b]' ? 2 : 3;
  const v = Array.isArray(value) ? [...value] : new Array(n).fill(0);
  const wrap = el('span', { className: 'vec' });
  const boxes = v.map((x, i) => {
    const box = el('input', { type: 'number', step: 'any', value: x });
    box.addEventListener('change', (e) => {
      v[i] = Number(box.value);
      send([...v], e.timeStamp);
    });
    wrap.append(box);
    return box;
  });
  const parts = [wrap];
  if (spec.type.startsWith('colour') && v.every((x) => x >= 0 && x <= 1)) {
    const hex = '#' + v.map((x) => Math.round(x * 255).toString(16).padStart(2, '0')).join('');
    const pick = el('input', { type: 'color', value: hex });
    pick.addEventListener('input', (e) => {
      const c = [1, 3, 5].map((i) => Number((parseInt(pick.value.substr(i, 2), 16) / 255).toFixed(3)));
      send(c, e.timeStamp);
    });
    parts.push(pick);
  }
  const set = (x) => {
    const w = typeof x === 'number' ? [x, x, x] : x;
    if (!Array.isArray(w)) return;
    w.forEach((c, i) => { if (boxes[i]) boxes[i].value = c; v[i] = c; });
  };
  return { parts, set };
}

// A field: label (with the doc as tooltip), control, reset button (removes the key: its default
// applies again). opts: {key, value, set, send(edit), keyframe(), animated, error, free: {on,
// set(on)} (a tick: the pin tool may solve for it)}.
export function field(spec, opts) {
  const set = opts.value !== undefined;
  const value = set ? opts.value : defaultOf(spec);
  const label = el('label', { textContent: spec.name,
    title: `${spec.name} (${spec.type}${spec.unit ? ', ' + spec.unit : ''}${rangeText(spec)})\n\n${spec.doc}` +
           (spec.default_note ? `\n\nDefault: ${spec.default_note}` : '') });
  const send = (v, t) => opts.send({ key: opts.key, value: v }, t);
  let ctl;
  if (spec.type === 'number' || spec.type === 'integer') {
    ctl = numberControl(spec, value, send);
    scrub(label, spec, () => Number(ctl.box.value || 0), (x, t) => { ctl.box.value = x; send(x, t); });
  } else if (spec.type === 'bool') {
    const c = el('input', { type: 'checkbox', checked: !!value });
    c.addEventListener('change', (e) => send(c.checked, e.timeStamp));
    ctl = { parts: [c], set: (x) => { c.checked = !!x; } };
  } else if (spec.type === 'string' && spec.choices.length) {
    const s = el('select');
    for (const c of spec.choices) s.append(el('option', { value: c, textContent: c }));
    s.value = value ?? '';
    s.addEventListener('change', (e) => send(s.value, e.timeStamp));
    ctl = { parts: [s], set: (x) => { s.value = x ?? ''; } };
  } else if (spec.type === 'string') {
    const t = el('input', { type: 'text', value: value ?? '', placeholder: spec.default_note || '' });
    t.addEventListener('change', (e) => send(t.value, e.timeStamp));
    ctl = { parts: [t], set: (x) => { t.value = x ?? ''; } };
  } else if (spec.type === '[a, b]' || spec.type === '[x, y, z]' ||
             ((spec.type === 'colour' || spec.type === 'colour or texture') &&
              (Array.isArray(value) || typeof value === 'number'))) {
    const v = typeof value === 'number' ? [value, value, value] : value;
    ctl = vectorControl(spec, v, send);
  } else {
    const t = el('textarea', { value: value === undefined ? '' : tomlText(value), spellcheck: false,
                               placeholder: spec.default_note || (spec.required ? 'required' : 'TOML') });
    t.addEventListener('change', (e) =>
      opts.send(t.value.trim() ? { key: opts.key, toml: t.value } : { key: opts.key, value: null }, e.timeStamp));
    ctl = { parts: [t], set: (x) => { t.value = x === undefined ? '' : tomlText(x); } };
  }
  const reset = el('button', { className: 'reset', textContent: '×', title: 'Back to the default (removes the key)' });
  reset.addEventListener('click', (e) => opts.send({ key: opts.key, value: null }, e.timeStamp));
  const row = el('div', { className: 'field' + (set ? ' set' : '') });
  row.dataset.key = opts.key;
  const c = el('div', { className: 'ctl' }, ...ctl.parts);
  if (opts.keyframe && (spec.type === 'number' || spec.type === '[x, y, z]')) {
    const k = el('button', { className: 'keyframe' + (opts.animated ? ' on' : ''), textContent: '◆',
                             title: 'Keyframe this value at the current frame' });
    k.addEventListener('click', () => opts.keyframe(opts.key, value));
    c.append(k);
  }
  if (opts.free) {  // (the pin tool solves for the keys ticked here: pins.js)
    const f = el('input', { type: 'checkbox', className: 'free', checked: opts.free.on,
                            title: 'Free: the pin tool may change this value' });
    f.addEventListener('change', () => opts.free.set(f.checked));
    c.append(f);
  }
  row.append(label, c, reset);
  if (opts.error) row.append(el('div', { className: 'err', textContent: opts.error }));
  // Shows the document's value again without rebuilding the row (the panels stay put while a
  // slider is dragged); a row the user is working in is left alone.
  c.addEventListener('pointerdown', () => (row.dataset.busy = '1'));
  c.addEventListener('pointerup', () => delete row.dataset.busy);
  row.refresh = (v) => {
    row.classList.toggle('set', v !== undefined);
    if (row.dataset.busy || row.contains(document.activeElement)) return;
    ctl.set(v !== undefined ? v : defaultOf(spec));
  };
  return row;
}

// Dragging a number's label left or right changes it (as in Blender), in steps that suit it.
function scrub(label, spec, get, set) {
  label.style.cursor = 'ew-resize';
  label.addEventListener('pointerdown', (down) => {
    const start = get(), x0 = down.clientX;
    const step = spec.type === 'integer' ? 0.2 : Math.max(Math.abs(start), 0.1) * 0.005;
    drag(label, down, (e) => {
      let x = start + (e.clientX - x0) * step;
      if (spec.min !== null) x = Math.max(spec.min, x);
      if (spec.max !== null) x = Math.min(spec.max, x);
      x = spec.type === 'integer' ? Math.round(x) : Number(x.toPrecision(5));
      set(x, e.timeStamp);
    });
  });
}

export { el };
