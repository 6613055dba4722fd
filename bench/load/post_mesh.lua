-- wrk script: POST /v1/map with one or two mesh files (mixed load: alternate requests).
-- Usage: wrk -s post_mesh.lua URL -- FILE [FILE2]
local bodies = {}

function init(args)
  for i = 1, #args do
    local f = assert(io.open(args[i], "rb"))
    bodies[i] = f:read("*all")
    f:close()
  end
end

local n = 0
function request()
  n = n + 1
  local body = bodies[(n % #bodies) + 1]
  return wrk.format("POST", "/v1/map", {["Content-Type"] = "model/gltf-binary"}, body)
end

local statuses = {}
function response(status)
  statuses[status] = (statuses[status] or 0) + 1
end

function done(summary, latency, requests)
  io.write(string.format("LOAD requests=%d seconds=%.1f rps=%.2f p50_ms=%.1f p90_ms=%.1f p99_ms=%.1f max_ms=%.1f non2xx=%d errors=%d\n",
    summary.requests, summary.duration / 1e6, summary.requests / (summary.duration / 1e6),
    latency:percentile(50) / 1000, latency:percentile(90) / 1000, latency:percentile(99) / 1000,
    latency.max / 1000, summary.errors.status,
    summary.errors.connect + summary.errors.read + summary.errors.write + summary.errors.timeout))
end
