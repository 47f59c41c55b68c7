// The server's API. Every call carries the access token in the cookie the page was served with
// (HttpOnly, SameSite=Strict); the address bar loses the token once the page has loaded, so a
// screenshot or a shared link does not give it away.
if (location.search.includes('token=')) history.replaceState(null, '', location.pathname);

export class ApiError extends Error {
  constructor(status, body) {
    super(body.error || `HTTP ${status}`);
    this.status = status;
    this.key = body.key;
    this.version = body.version;
  }
}

export async function get(path) {
  const r = await fetch(path, { cache: 'no-store' });
  const body = await r.json();
  if (!r.ok) throw new ApiError(r.status, body);
  return body;
}

export async function post(path, body = {}) {
  const r = await fetch(path, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  const text = await r.text();
  const json = text ? JSON.parse(text) : {};
  if (!r.ok) throw new ApiError(r.status, json);
  return json;
}

// The next preview frame after `seq` (long poll): {seq, version, width, height, pass, passes,
// coarse, seconds, pixels: Uint8ClampedArray} or null when none came in time.
export async function nextFrame(seq, signal) {
  const r = await fetch(`/api/frame?after=${seq}&timeout=20`, { cache: 'no-store', signal });
  if (r.status === 204) return null;
  if (!r.ok) throw new ApiError(r.status, await r.json());
  const h = (k) => Number(r.headers.get(`X-Frame-${k}`));
  return {
    seq: h('Seq'), version: h('Version'), width: h('Width'), height: h('Height'),
    pass: h('Pass'), passes: h('Passes'), coarse: h('Coarse') === 1, seconds: h('Seconds'),
    pixels: new Uint8ClampedArray(await r.arrayBuffer()),
  };
}
