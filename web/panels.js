// The sidebar: the camera (a preset, or an org/dir composition with each function's keys), its
// coins, the image and render tables, and the scene file as text. Everything is generated from
// the declarations (/api/declarations) and the document; nothing here names a parameter.
import { field, el, defaultOf } from './fields.js';
import { scenePanels } from './scene_panels.js';

const ANIMATABLE = new Set(['number', '[x, y, z]']);
// Keys the pin tool may solve for (a tick beside each): the camera's numbers and vectors.
const SOLVABLE = new Set(['number', '[a, b]', '[x, y, z]']);

export class Panels {
  constructor(root, decl, doc, hooks) {
    this.root = root;
    this.decl = decl;
    this.doc = doc;
    this.hooks = hooks;  // {keyframe(key, value), animated(key), selectCoin(i), selectedCoin()}
    this.errors = new Map();  // key -> message of the last refused edit
    this.open = new Set(['camera', 'coins']);
  }

  send(edit, t) {
    this.errors.delete(edit.key);
    this.doc.edit([edit], t);
  }

  showError(key, message) {
    if (!key) return false;
    this.errors.set(key, message);
    this.render();
    return true;
  }

  fields(specs, prefix, skip = new Set()) {
    return specs.filter((s) => !skip.has(s.name)).map((s) => {
      const key = prefix + s.name;
      return field(s, {
        key, value: this.doc.value(key), send: (e, t) => this.send(e, t), error: this.errors.get(key),
        keyframe: ANIMATABLE.has(s.type) ? this.hooks.keyframe : null, animated: this.hooks.animated(key),
        free: key.startsWith('camera.') && SOLVABLE.has(s.type) ?
          { on: this.hooks.free(key), set: (on) => this.hooks.setFree(key, on) } : null,
      });
    });
  }

  panel(id, title, note, ...body) {
    const d = el('details', { className: 'panel', open: this.open.has(id) });
    d.addEventListener('toggle', () => (d.open ? this.open.add(id) : this.open.delete(id)));
    d.append(el('summary', {}, title, el('span', { className: 'muted', textContent: note })),
             el('div', { className: 'panel-body' }, ...body));
    return d;
  }

  // What decides the panels' layout: a change of it rebuilds them, any other change updates the
  // values in place.
  signature() {
    const d = this.doc;
    return JSON.stringify([this.mode(), d.value('camera.preset'), d.value('camera.org.type'), d.value('camera.dir.type'),
      (d.value('camera.coin') || []).length, [...this.errors], (d.value('animate') || []).map((a) => a.key),
      ...['material', 'object', 'light'].map((k) => (d.value(k) || []).map((e) => e.type ?? '')),
      this.hooks.selectedCoin(), d.state.text.length > 0 && d.state.file]);
  }

  render() {
    const sig = this.signature();
    if (sig === this.lastSignature) {
      for (const row of this.root.querySelectorAll('.field')) row.refresh(this.doc.value(row.dataset.key));
      const text = this.root.querySelector('#scene-text');
      if (text) text.value = this.doc.state.text;
      return;
    }
    this.lastSignature = sig;
    const scroll = this.root.parentElement.scrollTop;
    this.root.replaceChildren(this.cameraPanel(), this.coinPanel(),
      this.panel('lens', 'Lens & shutter', 'every camera', ...this.fields(this.commonSpecs(), 'camera.')),
      this.panel('image', 'Image', '', ...this.fields(this.decl.image, 'image.')),
      this.panel('render', 'Render', '', ...this.fields(this.decl.render, 'render.')),
      ...scenePanels(this), this.filePanel());
    this.root.parentElement.scrollTop = scroll;
  }

  commonSpecs() {
    const structural = new Set(['preset', 'org', 'dir', 'coin', 'gltf_camera']);
    return this.decl.camera.filter((s) => !structural.has(s.name));
  }

  mode() {
    const cam = this.doc.value('camera') || {};
    if (cam.gltf_camera !== undefined) return 'gltf';
    return cam.org || cam.dir ? 'compose' : 'preset';
  }

  cameraPanel() {
    const mode = this.mode();
    const modeSel = el('select', { id: 'camera-mode' });
    modeSel.append(el('option', { value: 'preset', textContent: 'Preset' }),
                   el('option', { value: 'compose', textContent: 'Composition: org(u,v) + dir(u,v)' }));
    if (mode === 'gltf') modeSel.append(el('option', { value: 'gltf', textContent: 'Camera from a model' }));
    modeSel.value = mode;
    modeSel.addEventListener('change', (e) => this.switchMode(modeSel.value, e.timeStamp));
    const body = [el('div', { className: 'row' }, modeSel)];
    let note = '';
    if (mode === 'preset') {
      const name = this.doc.value('camera.preset') ?? 'perspective';
      const info = this.decl.presets[name];
      const sel = el('select', { id: 'preset' });
      for (const p of Object.keys(this.decl.presets)) sel.append(el('option', { value: p, textContent: p.replace(/_/g, ' ') }));
      sel.value = name;
      sel.addEventListener('change', (e) => this.switchPreset(sel.value, e.timeStamp));
      body.push(el('div', { className: 'row' }, sel), el('p', { className: 'hint', textContent: info ? info.doc : '' }));
      if (info) body.push(...this.fields(info.params, 'camera.'));
      note = name;
    } else if (mode === 'compose') {
      for (const which of ['org', 'dir']) {
        const type = this.doc.value(`camera.${which}.type`);
        const sel = el('select', { id: `${which}-type` });
        for (const t of Object.keys(this.decl[which])) sel.append(el('option', { value: t, textContent: t }));
        sel.value = type ?? '';
        sel.addEventListener('change', (e) => this.send({ key: `camera.${which}`, value: { type: sel.value } }, e.timeStamp));
        const info = this.decl[which][type];
        body.push(el('div', { className: 'row' }, el('strong', { textContent: which === 'org' ? 'org(u, v)' : 'dir(u, v)' }), sel),
                  el('p', { className: 'hint', textContent: info ? info.doc : '' }));
        if (info) body.push(...this.fields(info.params, `camera.${which}.`, new Set(['type'])));
      }
      note = `${this.doc.value('camera.org.type')} + ${this.doc.value('camera.dir.type')}`;
    }
    return this.panel('camera', 'Camera', note, ...body);
  }

  // A preset keeps the keys the new one declares too (look_from, fov, ...) and drops the others.
  switchPreset(name, t) {
    const keep = new Set(['preset', 'coin', ...this.decl.presets[name].params.map((s) => s.name),
                          ...this.decl.camera.map((s) => s.name)]);
    const edits = [{ key: 'camera.preset', value: name }];
    for (const k of Object.keys(this.doc.value('camera') || {}))
      if (!keep.has(k)) edits.push({ key: `camera.${k}`, value: null });
    this.doc.edit(edits, t);
  }

  switchMode(mode, t) {
    const cam = this.doc.value('camera') || {};
    const common = new Set(this.decl.camera.map((s) => s.name));
    const edits = [];
    for (const k of Object.keys(cam))
      if (k !== 'coin' && (!common.has(k) || k === 'gltf_camera')) edits.push({ key: `camera.${k}`, value: null });
    if (mode === 'compose') {
      // The paper's first example: rays along the outward normals of a sphere around the eye.
      const eye = cam.look_from || [0, 0, 0];
      edits.push({ key: 'camera.org', value: { type: 'sphere', center: eye, radius: 0.1 } },
                 { key: 'camera.dir', value: { type: 'normal' } });
    } else {
      edits.push({ key: 'camera.preset', value: 'perspective' });
    }
    this.doc.edit(edits, t);
  }

  coinPanel() {
    const coins = this.doc.value('camera.coin') || [];
    const body = [el('p', { className: 'hint', textContent:
      'Centers of interest magnify the image around a point of the scene. Choose the ◎ Coin tool and click the image to place one; drag it to move it, drag its ring to change its radius, use the wheel over it for strength (shift: stiffness).' })];
    coins.forEach((c, i) => {
      const card = el('div', { className: 'coin-card' + (this.hooks.selectedCoin() === i ? ' selected' : '') });
      const del = el('button', { textContent: 'Delete', title: 'Remove this coin' });
      del.addEventListener('click', (e) => this.doc.edit([{ key: 'camera.coin', value: coins.filter((_, j) => j !== i) }], e.timeStamp));
      const anim = el('button', { textContent: 'Animate strength from 0', title: "The paper's example: the coin's strength grows from 0 over the timeline" });
      anim.addEventListener('click', () => this.hooks.animateFromZero(`camera.coin.${i}.strength`, c.strength ?? defaultOf(this.decl.coin.find((s) => s.name === 'strength'))));
      card.addEventListener('click', () => this.hooks.selectCoin(i));
      card.append(el('h4', {}, `coin ${i}`, del), ...this.fields(this.decl.coin, `camera.coin.${i}.`), el('div', { className: 'row' }, anim));
      body.push(card);
    });
    return this.panel('coins', 'Coins', coins.length ? `${coins.length}` : 'none', ...body);
  }

  filePanel() {
    const st = this.doc.state;
    const text = el('textarea', { readOnly: true, value: st.text, rows: 14, spellcheck: false, id: 'scene-text' });
    text.style.width = '100%';
    const warnings = (st.warnings || []).map((w) => el('p', { className: 'hint', textContent: '⚠ ' + w }));
    return this.panel('file', 'Scene file', st.file, ...warnings, text);
  }
}
