-- wrk script for the mixed soak: rotates through valid jobs (async and synchronous), a
-- mesh that is not genus 0, hostile bytes, a wrong content type and unknown job ids.
-- Usage: wrk -s mixed_jobs.lua URL -- SMALL.glb MEDIUM.glb BAD.glb
local files = {}

function init(args)
  for i = 1, #args do
    local f = assert(io.open(args[i], "rb"))
    files[i] = f:read("*all")
    f:close()
  end
end

local n = 0
function request()
  n = n + 1
  local k = n % 8
  local glb = {["Content-Type"] = "model/gltf-binary"}
  if k == 0 then return wrk.format("POST", "/v1/jobs", glb, files[1]) end
  if k == 1 then return wrk.format("POST", "/v1/map", glb, files[2]) end
  if k == 2 then return wrk.format("POST", "/v1/jobs?prepare=parts&max_handle_cycle=0", glb, files[3]) end -- 422 (handle kept)
  if k == 3 then return wrk.format("POST", "/v1/jobs", glb, files[1]:sub(1, 3000)) end  -- 400
  if k == 4 then return wrk.format("POST", "/v1/jobs", glb, string.rep("\255", 512)) end -- 400
  if k == 5 then return wrk.format("POST", "/v1/jobs", {["Content-Type"] = "text/plain"}, "x") end
  if k == 6 then return wrk.format("GET", "/v1/jobs/0123456789abcdef0123456789abcdef") end -- 404
  return wrk.format("POST", "/v1/map?outputs=remesh,uv,morph&resolution=32", glb, files[1])
end

function done(summary, latency, requests)
  io.write(string.format("LOAD requests=%d seconds=%.1f rps=%.2f p50_ms=%.1f p99_ms=%.1f max_ms=%.1f non2xx=%d errors=%d\n",
    summary.requests, summary.duration / 1e6, summary.requests / (summary.duration / 1e6),
    latency:percentile(50) / 1000, latency:percentile(99) / 1000, latency.max / 1000,
    summary.errors.status,
    summary.errors.connect + summary.errors.read + summary.errors.write + summary.errors.timeout))
end
