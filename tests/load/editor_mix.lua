-- wrk script for the editor's load test (tests/load/editor_load.py): what a busy page does.
-- Half of wrk's threads poll the preview as the page does (a long poll for the frame after the
-- last one seen); the others edit the camera (fov, with the document's version, so concurrent
-- editors meet the first-writer-wins rule), read the state, pick, project, ask for the coins and
-- the magnification map, undo and redo. Every status is counted per thread; done() prints them
-- as one JSON line for the driver.
local token = os.getenv("ANAMORPH_TOKEN") or ""
local threads = {}
local counter = 1

function setup(thread)
  thread:set("id", counter)
  table.insert(threads, thread)
  counter = counter + 1
end

function init(args)
  statuses = {}
  role = (id % 2 == 1) and "poll" or "edit"
  seq = 0        -- the newest preview frame this thread has seen
  version = 1    -- the newest document version this thread has seen
  n = 0
  edits_ok, stale = 0, 0
  headers = { ["X-Anamorph-Token"] = token, ["Content-Type"] = "application/json" }
end

local function edit_request()
  local fov = 40 + (n * 7 + id) % 50
  local body = string.format('{"version": %d, "edits": [{"key": "camera.fov", "value": %d}]}',
                             version, fov)
  return wrk.format("POST", "/api/edit", headers, body)
end

function request()
  n = n + 1
  if role == "poll" then
    return wrk.format("GET", string.format("/api/frame?after=%d&timeout=5", seq), headers)
  end
  local k = n % 10
  if k <= 3 then return edit_request() end
  if k == 4 then return wrk.format("GET", "/api/state", headers) end
  if k == 5 then
    return wrk.format("POST", "/api/pick", headers,
                      string.format('{"u": %.3f, "v": %.3f}', (n % 97) / 97, (n % 89) / 89))
  end
  if k == 6 then
    return wrk.format("POST", "/api/project", headers, '{"position": [0, 0.8, 0]}')
  end
  if k == 7 then return wrk.format("GET", "/api/coins", headers) end
  if k == 8 then return wrk.format("GET", "/api/magnification?width=64&height=36", headers) end
  return wrk.format("POST", (n % 20 < 10) and "/api/undo" or "/api/redo", headers, "{}")
end

function response(status, hdrs, body)
  statuses[status] = (statuses[status] or 0) + 1
  if role == "poll" then
    local s = hdrs["X-Frame-Seq"]
    if s then seq = tonumber(s) end
    return
  end
  local v = body:match('^{"version":(%d+)') or body:match('"version":(%d+)')
  if v then version = tonumber(v) end
  if status == 409 then stale = stale + 1 end
end

function done(summary, latency, requests)
  local total = {}
  for _, t in ipairs(threads) do
    for code, count in pairs(t:get("statuses")) do
      total[code] = (total[code] or 0) + count
    end
  end
  local parts = {}
  for code, count in pairs(total) do
    table.insert(parts, string.format('"%d": %d', code, count))
  end
  io.write(string.format(
    'WRK_RESULT {"statuses": {%s}, "requests": %d, "seconds": %.3f, ' ..
    '"errors": {"connect": %d, "read": %d, "write": %d, "status": %d, "timeout": %d}, ' ..
    '"latency_ms": {"p50": %.2f, "p99": %.2f, "max": %.2f}}\n',
    table.concat(parts, ", "), summary.requests, summary.duration / 1e6,
    summary.errors.connect, summary.errors.read, summary.errors.write, summary.errors.status,
    summary.errors.timeout, latency:percentile(50) / 1000, latency:percentile(99) / 1000,
    latency.max / 1000))
end
