// The Lua scripts that change the Redis queue's state (redis_queue.h says what each key
// holds). Each runs atomically in Redis, so replicas and worker nodes never race: two
// submissions cannot both take the last queue slot, a cancel cannot slip between a
// worker's start and its first heartbeat, a finish and an eviction cannot double-count.
// Keys a script derives from an id or a tenant are built from the prefix in ARGV (one
// Redis, not a cluster).
#pragma once

namespace spheremap::server::redis_scripts {

// KEYS: queued, tenant's queued, job hash, spec, stream, sequence, the id's void marker,
// the tenant's Idempotency-Key ("" = none). ARGV: id, capacity, tenant capacity, now
// (ms), spec bytes, deadline (ms, Redis's clock), the key's TTL (s), prefix, then the
// hash's field/value pairs.
// Returns {0} accepted, {1} queue full, {2} tenant's queue full, {3} id taken, {4, id}
// the key's job (kept: no new one), {5} too late or voided: the submitter gave up on
// this id (a 503) before Redis ran it, so it must not be stored. The queue orders by a
// sequence number, not the clock: two jobs submitted in one millisecond keep their order.
inline constexpr const char* kSubmit = R"lua(
local time = redis.call('TIME')
local now = tonumber(time[1]) * 1000 + math.floor(tonumber(time[2]) / 1000)
if now > tonumber(ARGV[6]) or redis.call('EXISTS', KEYS[7]) == 1 then return {5} end
if KEYS[8] ~= '' then
  local earlier = redis.call('GET', KEYS[8])
  if earlier and redis.call('EXISTS', ARGV[8] .. 'job:' .. earlier) == 1 then
    return {4, earlier}
  end
end
if redis.call('ZCARD', KEYS[1]) >= tonumber(ARGV[2]) then return {1} end
if redis.call('ZCARD', KEYS[2]) >= tonumber(ARGV[3]) then return {2} end
if redis.call('EXISTS', KEYS[3]) == 1 then return {3} end
local seq = redis.call('INCR', KEYS[6])
redis.call('HSET', KEYS[3], 'seq', seq, unpack(ARGV, 9))
redis.call('SET', KEYS[4], ARGV[5])
redis.call('ZADD', KEYS[1], seq, ARGV[1])
redis.call('ZADD', KEYS[2], seq, ARGV[1])
redis.call('XADD', KEYS[5], '*', 'job', ARGV[1])
if KEYS[8] ~= '' then redis.call('SET', KEYS[8], ARGV[1], 'EX', ARGV[7]) end
return {0}
)lua";

// KEYS: job hash, the id's void marker. ARGV: the marker's TTL (s). After a submission
// whose answer was lost (a timeout): 'stored' when it ran, else 'void', and the marker
// makes the submission refuse itself if it reaches Redis later.
inline constexpr const char* kSettle = R"lua(
if redis.call('EXISTS', KEYS[1]) == 1 then return 'stored' end
redis.call('SET', KEYS[2], '1', 'EX', ARGV[1])
return 'void'
)lua";

// KEYS: job hash, queued, stream. ARGV: id, now (ms), max attempts, node, prefix, entry,
// the tenant's running cap (0 = none). Returns 'skip' (the job ended or vanished: its
// entry is acknowledged), 'later' (its tenant already runs as many jobs as it may: the
// job goes to the back of the stream, still queued), 'poison' (its workers died max
// attempts times; it is marked running so that it can be finished as failed) or 'run',
// with the attempt's number. tenant:T:running counts a tenant's jobs started and not
// finished or released; a job reclaimed from a dead node is not counted twice.
inline constexpr const char* kStart = R"lua(
local status = redis.call('HGET', KEYS[1], 'status')
if status ~= 'queued' and status ~= 'running' then
  redis.call('XACK', KEYS[3], 'workers', ARGV[6])
  redis.call('XDEL', KEYS[3], ARGV[6])
  return {'skip', 0}
end
local tenant = redis.call('HGET', KEYS[1], 'tenant')
local running = ARGV[5] .. 'tenant:' .. tenant .. ':running'
if status == 'queued' then
  local cap = tonumber(ARGV[7])
  if cap > 0 and tonumber(redis.call('GET', running) or '0') >= cap then
    redis.call('XACK', KEYS[3], 'workers', ARGV[6])
    redis.call('XDEL', KEYS[3], ARGV[6])
    redis.call('XADD', KEYS[3], '*', 'job', ARGV[1])
    return {'later', 0}
  end
  redis.call('INCR', running)
end
redis.call('ZREM', KEYS[2], ARGV[1])
redis.call('ZREM', ARGV[5] .. 'tenant:' .. tenant .. ':queued', ARGV[1])
local attempts = redis.call('HINCRBY', KEYS[1], 'attempts', 1)
redis.call('HSET', KEYS[1], 'status', 'running', 'started_ms', ARGV[2], 'node', ARGV[4],
           'progress', '{"stage":"starting"}')
if attempts > tonumber(ARGV[3]) then return {'poison', attempts - 1} end
return {'run', attempts}
)lua";

// KEYS: job hash, files, finished, sizes, result_bytes, stream, gone, spec, this
// delivery's files, the tenant's running count. ARGV: id, entry, status, now (ms), ttl (s),
// artifact bytes, counter key, prefix, then the hash's field/value pairs. The job's bytes
// are also counted for its tenant (owners: id -> tenant; tenant_bytes: tenant -> bytes;
// tenant:T:finished by end time), for tenant_result_memory_bytes. The worker wrote its artifacts
// under a key of its own delivery; they become the job's files only if the job is still running. A
// job no longer running (cancelled, removed, or finished by another worker that reclaimed it while
// this one was presumed dead) keeps its state and its files; this worker's are dropped.
inline constexpr const char* kFinish = R"lua(
redis.call('XACK', KEYS[6], 'workers', ARGV[2])
redis.call('XDEL', KEYS[6], ARGV[2])
if redis.call('HGET', KEYS[1], 'status') ~= 'running' then
  redis.call('DEL', KEYS[9])
  return 0
end
if redis.call('EXISTS', KEYS[9]) == 1 then redis.call('RENAME', KEYS[9], KEYS[2]) end
if tonumber(redis.call('GET', KEYS[10]) or '0') > 0 then redis.call('DECR', KEYS[10]) end
redis.call('HSET', KEYS[1], 'status', ARGV[3], 'finished_ms', ARGV[4], unpack(ARGV, 9))
redis.call('HDEL', KEYS[1], 'cancel')
redis.call('EXPIRE', KEYS[1], ARGV[5])
redis.call('EXPIRE', KEYS[2], ARGV[5])
redis.call('SET', KEYS[7], 'ended', 'EX', tonumber(ARGV[5]) + 86400)
redis.call('DEL', KEYS[8])
redis.call('ZADD', KEYS[3], ARGV[4], ARGV[1])
redis.call('HSET', KEYS[4], ARGV[1], ARGV[6])
redis.call('INCRBY', KEYS[5], ARGV[6])
redis.call('INCR', ARGV[7])
local tenant = redis.call('HGET', KEYS[1], 'tenant') or ''
redis.call('HSET', ARGV[8] .. 'owners', ARGV[1], tenant)
redis.call('HINCRBY', ARGV[8] .. 'tenant_bytes', tenant, ARGV[6])
redis.call('ZADD', ARGV[8] .. 'tenant:' .. tenant .. ':finished', ARGV[4], ARGV[1])
return 1
)lua";

// KEYS: job hash, queued, stream. ARGV: id, entry, prefix, count attempt (0/1). Puts a
// running job back at its place in the queue under a new entry.
inline constexpr const char* kRelease = R"lua(
redis.call('XACK', KEYS[3], 'workers', ARGV[2])
redis.call('XDEL', KEYS[3], ARGV[2])
if redis.call('HGET', KEYS[1], 'status') ~= 'running' then return 0 end
local created = redis.call('HGET', KEYS[1], 'seq')
local tenant = redis.call('HGET', KEYS[1], 'tenant')
redis.call('HSET', KEYS[1], 'status', 'queued', 'progress', '{"stage":"queued"}')
redis.call('HDEL', KEYS[1], 'started_ms', 'node')
if ARGV[4] == '0' then redis.call('HINCRBY', KEYS[1], 'attempts', -1) end
local running = ARGV[3] .. 'tenant:' .. tenant .. ':running'
if tonumber(redis.call('GET', running) or '0') > 0 then redis.call('DECR', running) end
redis.call('ZADD', KEYS[2], created, ARGV[1])
redis.call('ZADD', ARGV[3] .. 'tenant:' .. tenant .. ':queued', created, ARGV[1])
redis.call('XADD', KEYS[3], '*', 'job', ARGV[1])
return 1
)lua";

// KEYS: job hash. ARGV: progress (JSON). A worker's heartbeat: publishes the progress of a
// job still running (never recreating the hash of one that ended and was evicted while
// its worker was storing the result) and returns its cancel flag ('1', or '').
inline constexpr const char* kHeartbeat = R"lua(
if redis.call('HGET', KEYS[1], 'status') ~= 'running' then return '' end
redis.call('HSET', KEYS[1], 'progress', ARGV[1])
return redis.call('HGET', KEYS[1], 'cancel') or ''
)lua";

// KEYS: job hash, queued, finished, sizes, gone, spec. ARGV: id, reason, now (ms), ttl
// (s), prefix. Returns 'cancelled' (it was queued), 'stopping' (running: its worker sees
// the flag with its next heartbeat), 'finished' or 'missing'.
inline constexpr const char* kCancel = R"lua(
local status = redis.call('HGET', KEYS[1], 'status')
if not status then return 'missing' end
if status == 'queued' then
  local tenant = redis.call('HGET', KEYS[1], 'tenant')
  redis.call('HSET', KEYS[1], 'status', 'cancelled', 'finished_ms', ARGV[3],
             'cancel_reason', ARGV[2], 'progress', '{"stage":"cancelled"}')
  redis.call('ZREM', KEYS[2], ARGV[1])
  redis.call('ZREM', ARGV[5] .. 'tenant:' .. tenant .. ':queued', ARGV[1])
  redis.call('EXPIRE', KEYS[1], ARGV[4])
  redis.call('SET', KEYS[5], 'ended', 'EX', tonumber(ARGV[4]) + 86400)
  redis.call('DEL', KEYS[6])
  redis.call('ZADD', KEYS[3], ARGV[3], ARGV[1])
  redis.call('HSET', KEYS[4], ARGV[1], 0)
  redis.call('INCR', ARGV[5] .. 'count:cancelled')
  return 'cancelled'
end
if status == 'running' then
  if not redis.call('HGET', KEYS[1], 'cancel_reason') then
    redis.call('HSET', KEYS[1], 'cancel_reason', ARGV[2])
  end
  redis.call('HSET', KEYS[1], 'cancel', '1')
  return 'stopping'
end
return 'finished'
)lua";

// KEYS: finished, sizes, result_bytes. ARGV: prefix, now (ms), ttl (ms), memory cap
// (bytes), jobs kept, the id to forget now or '', the cap per tenant (bytes). Drops
// finished jobs past the TTL, then each tenant's own oldest while that tenant is over its
// cap (never another tenant's), then the oldest while over the caps; their gone: keys stay
// (410). With an id: forgets that finished job entirely (DELETE), gone: key too; returns
// 1 if it was finished.
inline constexpr const char* kEvict = R"lua(
local p = ARGV[1]
local function drop(id)
  local size = tonumber(redis.call('HGET', KEYS[2], id) or '0')
  redis.call('DECRBY', KEYS[3], size)
  redis.call('HDEL', KEYS[2], id)
  redis.call('ZREM', KEYS[1], id)
  redis.call('DEL', p .. 'job:' .. id, p .. 'files:' .. id)
  local tenant = redis.call('HGET', p .. 'owners', id)
  if tenant then
    redis.call('HDEL', p .. 'owners', id)
    redis.call('ZREM', p .. 'tenant:' .. tenant .. ':finished', id)
    -- 0 - size, not -size: Lua writes -0 as "-0", which Redis refuses as an integer
    if redis.call('HINCRBY', p .. 'tenant_bytes', tenant, 0 - size) <= 0 then
      redis.call('HDEL', p .. 'tenant_bytes', tenant)
    end
  end
end
if ARGV[6] ~= '' then
  if not redis.call('ZSCORE', KEYS[1], ARGV[6]) then return 0 end
  drop(ARGV[6])
  redis.call('DEL', p .. 'gone:' .. ARGV[6])
  return 1
end
local evicted = 0
local old = redis.call('ZRANGEBYSCORE', KEYS[1], '-inf', tonumber(ARGV[2]) - tonumber(ARGV[3]),
                       'LIMIT', 0, 1000)
for _, id in ipairs(old) do drop(id); evicted = evicted + 1 end
local share = tonumber(ARGV[7])
local tenants = redis.call('HGETALL', p .. 'tenant_bytes')
for i = 1, #tenants, 2 do
  local tenant = tenants[i]
  while tonumber(redis.call('HGET', p .. 'tenant_bytes', tenant) or '0') > share do
    local oldest = redis.call('ZRANGE', p .. 'tenant:' .. tenant .. ':finished', 0, 0)
    if #oldest == 0 then redis.call('HDEL', p .. 'tenant_bytes', tenant); break end
    drop(oldest[1])
    evicted = evicted + 1
  end
end
while tonumber(redis.call('GET', KEYS[3]) or '0') > tonumber(ARGV[4]) or
      redis.call('ZCARD', KEYS[1]) > tonumber(ARGV[5]) do
  local oldest = redis.call('ZRANGE', KEYS[1], 0, 0)
  if #oldest == 0 then break end
  drop(oldest[1])
  evicted = evicted + 1
end
if evicted > 0 then redis.call('INCRBY', p .. 'count:evicted', evicted) end
return evicted
)lua";

}  // namespace spheremap::server::redis_scripts
