// The scene document as the page knows it: the tree (JSON of the TOML), its version, and the
// edits on their way. Edits go one request at a time; those made meanwhile are merged by key and
// sent together when the answer comes, so a dragged slider costs one render per answer, not one
// per mouse move. A 409 means another tab changed the scene first: its version wins, and this
// tab reloads.
import { post, get, ApiError } from './api.js';

export class Doc extends EventTarget {
  constructor() {
    super();
    this.state = null;      // /api/state
    this.pending = new Map();  // key -> {value} | {toml}
    this.inflight = false;
    this.inputTimes = [];   // [performance.now() of the input, version it produced]
  }
  get version() { return this.state ? this.state.version : 0; }
  get tree() { return this.state ? this.state.document : {}; }

  async reload() {
    this.adopt(await get('/api/state'));
  }

  adopt(state) {
    if (this.state && state.version < this.state.version) return;  // (an older answer)
    this.state = state;
    this.dispatchEvent(new Event('change'));
  }

  // The value at a dotted key of the document (undefined when not written).
  value(key) {
    let cur = this.tree;
    for (const part of key.split('.')) {
      if (cur === undefined || cur === null) return undefined;
      cur = Array.isArray(cur) ? cur[Number(part)] : cur[part];
    }
    return cur;
  }

  // Queues edits: [{key, value}] (value null removes the key) or [{key, toml}].
  edit(edits, inputTime = performance.now()) {
    for (const e of edits) this.pending.set(e.key, e);
    this.lastInput = inputTime;
    this.flush();
  }

  async flush() {
    if (this.inflight || this.pending.size === 0) return;
    const edits = [...this.pending.values()];
    const input = this.lastInput;
    this.pending.clear();
    this.inflight = true;
    try {
      const r = await post('/api/edit', { version: this.version, edits });
      this.inputTimes.push([input, r.version]);
      this.adopt(r.state);
      this.dispatchEvent(new CustomEvent('edited', { detail: { edits, warnings: r.warnings } }));
    } catch (e) {
      if (e instanceof ApiError && e.status === 409) {
        await this.reload();
        this.dispatchEvent(new CustomEvent('problem', { detail: { message: 'The scene was changed in another tab; this edit was not applied, the panels now show the scene as it is.' } }));
      } else {
        this.dispatchEvent(new CustomEvent('problem', { detail: { message: e.message, key: e.key } }));
        this.dispatchEvent(new Event('change'));  // the panels show the document's value again
      }
    } finally {
      this.inflight = false;
      this.flush();
    }
  }

  async action(path, body = {}) {
    try {
      const r = await post(path, body);
      if (r.version !== undefined) this.inputTimes.push([performance.now(), r.version]);
      if (r.state) this.adopt(r.state);
      else await this.reload();
      return r;
    } catch (e) {
      this.dispatchEvent(new CustomEvent('problem', { detail: { message: e.message, key: e.key } }));
      if (e instanceof ApiError && e.status === 409) await this.reload();
      return null;
    }
  }
}
