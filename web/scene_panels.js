// The scene's own tables as panels: materials, objects, lights (arrays of entries, each a card
// with its form's keys), the environment and the keyframes. Generated from the declarations'
// `tables`, like the camera's panels: a key or a form added in C++ appears here by itself.
import { el } from './fields.js';

const SHOWN = [['material', 'Materials'], ['object', 'Objects'], ['light', 'Lights'],
               ['environment', 'Environment'], ['animate', 'Keyframes']];

export function scenePanels(panels) {
  const tables = panels.decl.tables || {};
  return SHOWN.filter(([key]) => tables[key]).map(([key, title]) => {
    const t = tables[key];
    if (!t.array) return panels.panel(key, title, '', el('p', { className: 'hint', textContent: t.doc }), ...panels.fields(t.common, `${key}.`));
    const entries = panels.doc.value(key) || [];
    const cards = entries.map((entry, i) => entryCard(panels, key, t, entry, i, entries));
    return panels.panel(key, title, `${entries.length}`, el('p', { className: 'hint', textContent: t.doc }), ...cards, addRow(panels, key, t, entries));
  });
}

// One entry: its form (the selector), the common keys and the form's own.
function entryCard(panels, key, t, entry, i, entries) {
  const sel = t.selector;
  const form = sel ? entry[sel] ?? t.common.find((s) => s.name === sel)?.default?.replace(/"/g, '') : null;
  const name = entry.name ? ` “${entry.name}”` : entry.key ? ` ${entry.key}` : '';
  const card = el('details', { className: 'coin-card', open: panels.open.has(`${key}.${i}`) });
  card.addEventListener('toggle', () => (card.open ? panels.open.add(`${key}.${i}`) : panels.open.delete(`${key}.${i}`)));
  const del = el('button', { textContent: 'Delete' });
  del.addEventListener('click', (e) => panels.doc.edit([{ key, value: entries.filter((_, j) => j !== i) }], e.timeStamp));
  const body = [];
  if (sel && t.variants && Object.keys(t.variants).length) {
    const s = el('select');
    for (const v of Object.keys(t.variants)) s.append(el('option', { value: v, textContent: v }));
    s.value = form;
    // A new form keeps the keys every form has and drops the old form's own.
    s.addEventListener('change', (e) => {
      const common = new Set(t.common.map((c) => c.name));
      const next = Object.fromEntries(Object.entries(entry).filter(([k]) => common.has(k)));
      next[sel] = s.value;
      panels.doc.edit([{ key: `${key}.${i}`, value: next }], e.timeStamp);
    });
    body.push(el('div', { className: 'row' }, el('strong', { textContent: sel }), s),
              el('p', { className: 'hint', textContent: t.variants[form]?.doc || '' }));
  }
  body.push(...panels.fields(t.common, `${key}.${i}.`, new Set([sel])));
  if (form && t.variants?.[form]) body.push(...panels.fields(t.variants[form].params, `${key}.${i}.`));
  card.append(el('summary', {}, `${key} ${i}${form ? ' · ' + form : ''}${name}`), el('div', {}, ...body, el('div', { className: 'row' }, del)));
  return card;
}

// Adds an entry of a chosen form (its required keys then need values: the reader says which).
function addRow(panels, key, t, entries) {
  const add = el('button', { textContent: `Add ${key}` });
  let choose = null;
  if (t.selector && t.variants && Object.keys(t.variants).length) {
    choose = el('select');
    for (const v of Object.keys(t.variants)) choose.append(el('option', { value: v, textContent: v }));
  }
  add.addEventListener('click', (e) => {
    const entry = choose ? { [t.selector]: choose.value } : {};
    panels.open.add(`${key}.${entries.length}`);
    panels.doc.edit([{ key, value: [...entries, entry] }], e.timeStamp);
  });
  return el('div', { className: 'row' }, ...(choose ? [choose] : []), add);
}
