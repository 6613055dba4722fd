"""Hostile requests against a running spheremap server (tests/attack/run.sh starts it
under a memory cap). Each attack must get its specific 4xx; meanwhile slow clients hold
API connections open and a prober times GET /healthz on the health port, which must
answer every time within 2 s. Prints one line per attack; exits 1 on the first failure.
Usage: attack.py API_URL HEALTH_URL GLB_FILE"""
import http.client
import json
import os
import socket
import struct
import sys
import threading
import time
import urllib.parse

api, health, glb_path = sys.argv[1:4]
api_host, api_port = urllib.parse.urlsplit(api).hostname, urllib.parse.urlsplit(api).port
glb = open(glb_path, "rb").read()


def fail(message):
    print("FAIL: " + message, flush=True)
    os._exit(1)  # not sys.exit: the prober and trickler threads would keep the process up


def request(method, path, body=None, headers=None, timeout=30):
    connection = http.client.HTTPConnection(api_host, api_port, timeout=timeout)
    connection.request(method, path, body=body, headers=headers or {})
    response = connection.getresponse()
    data = response.read()
    connection.close()
    return response.status, data


def raw_status(text, body_bytes=b""):
    """Sends raw bytes; returns the status line (the answer may come before the body)."""
    s = socket.create_connection((api_host, api_port), timeout=30)
    s.sendall(text.encode() + body_bytes)
    answer = b""
    while b"\r\n" not in answer:
        chunk = s.recv(4096)
        if not chunk:
            break
        answer += chunk
    s.close()
    return answer.split(b"\r\n", 1)[0].decode(errors="replace")


def expect(name, status, body, want_status, want_type=None):
    if status != want_status:
        fail(f"{name}: {status}, expected {want_status}: {body[:300]!r}")
    if want_type:
        problem = json.loads(body)
        if not problem.get("type", "").endswith("/" + want_type):
            fail(f"{name}: problem {problem.get('type')}, expected {want_type}")
    print(f"{name}: {status}" + (f" {want_type}" if want_type else ""))


# The prober: GET /healthz on the health port every 100 ms for the whole suite.
worst = [0.0]
probe_failures = []
stop = threading.Event()


def probe():
    host, port = urllib.parse.urlsplit(health).hostname, urllib.parse.urlsplit(health).port
    while not stop.is_set():
        start = time.monotonic()
        try:
            c = http.client.HTTPConnection(host, port, timeout=5)
            c.request("GET", "/healthz")
            if c.getresponse().status != 200:
                probe_failures.append("status")
            c.close()
        except OSError as e:
            probe_failures.append(str(e))
        worst[0] = max(worst[0], time.monotonic() - start)
        time.sleep(0.1)


# Slow clients from one address (127.0.0.2: 127.0.0.1 is exempt from the per-address cap),
# more than the API has threads, each trickling a header line a second: the first
# max_connections_per_address are served until header_timeout_seconds ends them with
# 408, the others get 429 at once; meanwhile the API port itself still answers.
slow = []
SLOW_SOURCE = ("127.0.0.2", 0)


def slowloris(count):
    for _ in range(count):
        s = socket.create_connection((api_host, api_port), timeout=60, source_address=SLOW_SOURCE)
        s.sendall(b"GET /healthz HTTP/1.1\r\nHost: x\r\n")
        slow.append(s)


def trickle():
    while not stop.is_set():
        for s in slow:
            try:
                s.sendall(b"X-a: b\r\n")
            except OSError:
                pass
        time.sleep(1)


def answer_of(s, seconds):
    s.settimeout(seconds)
    try:
        return s.recv(4096).split(b"\r\n", 1)[0].decode(errors="replace")
    except OSError:
        return ""


prober = threading.Thread(target=probe)
prober.start()
start = time.monotonic()
slowloris(12)
trickler = threading.Thread(target=trickle)
trickler.start()
time.sleep(0.5)
status, body = request("GET", "/healthz", timeout=5)
if status != 200:
    fail(f"/healthz on the API port during slowloris: {status}")
answers = [answer_of(s, 6) for s in slow]
took = time.monotonic() - start
for s in slow:
    s.close()
slow.clear()
refused = sum(a.startswith("HTTP/1.1 429") for a in answers)
timed_out = sum(a.startswith("HTTP/1.1 408") for a in answers)
if refused != 9 or timed_out != 3:
    fail(f"slowloris: {refused} answered 429 and {timed_out} 408, expected 9 and 3: {answers}")
if took > 4:
    fail(f"slowloris: the last trickling connection was ended after {took:.1f} s")
print(f"slowloris: 12 trickling connections from one address: 9 refused at once (429), 3 ended "
      f"after the 2 s header deadline (408) by {took:.1f} s; the API port answered meanwhile; "
      f"/healthz on the health port at most {worst[0]:.3f} s")

many = "GET /healthz HTTP/1.1\r\nHost: x\r\n" + "".join(f"X-{k}: v\r\n" for k in range(5000))
line = raw_status(many + "\r\n")
if not line.startswith("HTTP/1.1 431"):
    fail("5,000 header lines: " + line)
print("5,000 header lines: 431")
s = socket.create_connection((api_host, api_port), timeout=30)
s.sendall(b"POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
          b"Content-Length: 100000\r\n\r\nglTF")
line = ""
for _ in range(60):
    try:
        s.sendall(b"x")
    except OSError:
        pass
    line = answer_of(s, 0.1)
    if line:
        break
s.close()
if not line.startswith("HTTP/1.1 408"):
    fail("body trickled a byte per 100 ms: " + line)
print("body trickled a byte per 100 ms: 408 after the 2 s body deadline")

deep = "[" * 60000 + "]" * 60000
boundary = "b0undary"
form = (f"--{boundary}\r\nContent-Disposition: form-data; name=\"mesh\"; filename=\"m.glb\"\r\n"
        f"Content-Type: model/gltf-binary\r\n\r\n").encode() + glb + (
        f"\r\n--{boundary}\r\nContent-Disposition: form-data; name=\"options\"\r\n"
        f"Content-Type: application/json\r\n\r\n{deep}\r\n--{boundary}--\r\n").encode()
status, body = request("POST", "/v1/jobs", form,
                       {"Content-Type": f"multipart/form-data; boundary={boundary}"})
expect("options nested 60,000 deep", status, body, 400, "invalid_options")

deep_gltf = '{"asset":{"version":"2.0"},"scene":' + deep + "}"
status, body = request("POST", "/v1/jobs", deep_gltf, {"Content-Type": "model/gltf+json"})
expect("glTF nested 60,000 deep", status, body, 400, "malformed_gltf")

nodes = [{"children": [k + 1, k + 1]} if k + 1 < 40 else {} for k in range(40)]
graph = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": nodes,
         "meshes": [{"primitives": []}]}
status, body = request("POST", "/v1/jobs", json.dumps(graph), {"Content-Type": "model/gltf+json"})
expect("node graph with 2^40 paths", status, body, 400, "malformed_gltf")

huge = {"asset": {"version": "2.0"},
        "buffers": [{"byteLength": 12, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}],
        "bufferViews": [{"buffer": 0, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 1000000000,
                       "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}
status, body = request("POST", "/v1/jobs", json.dumps(huge), {"Content-Type": "model/gltf+json"})
expect("accessor declaring 10^9 vertices over 12 bytes", status, body, 400, "malformed_gltf")

ranges = "bytes=0-1" + ",0-1" * 1500
status, body = request("GET", "/v1/openapi.yaml", headers={"Range": ranges})
expect("1,500 overlapping ranges", status, body, 416, "too_many_ranges")

head = "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
line = raw_status(head + "Transfer-Encoding: chunked\r\n\r\n")
if not line.startswith("HTTP/1.1 411"):
    fail("chunked body: " + line)
print("chunked body (max_body_bytes unseen): 411")
line = raw_status(head + "Content-Encoding: gzip\r\nContent-Length: 8000000\r\n\r\n")
if not line.startswith("HTTP/1.1 415"):
    fail("gzip body: " + line)
print("gzip body (a zip bomb): 415")
line = raw_status(head + "Content-Length: 4000000000\r\n\r\n", b"x" * 65536)
if not line.startswith("HTTP/1.1 413"):
    fail("4 GB declared body: " + line)
print("4 GB declared body: 413")

status, body = request("POST", "/v1/jobs?draco=true&draco_position_bits=30", glb,
                       {"Content-Type": "model/gltf-binary"})
expect("draco_position_bits=30", status, body, 400, "invalid_options")

status, body = request("POST", "/v1/jobs", b"\x00" * 1000, {"Content-Type": "model/gltf-binary"})
expect("1,000 zero bytes as GLB", status, body, 400, "malformed_gltf")

# Hostile STL and PLY (Reach I): counts declared far past the bytes sent, a truncated
# binary PLY, non-finite coordinates, indices out of range: each a 400 read from the counts
# before anything is allocated for them.
ply_head = ("ply\nformat binary_little_endian 1.0\nelement vertex {v}\nproperty float x\n"
            "property float y\nproperty float z\nelement face {f}\n"
            "property list uchar int vertex_indices\nend_header\n")
corners = b"".join(struct.pack("<fff", *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)])
faces = b"".join(struct.pack("<Biii", 3, *t) for t in [(0, 1, 2), (0, 1, 3)])
nan_stl = "solid x\n" + "".join(
    " facet normal 0 0 0\n  outer loop\n" +
    "".join(f"   vertex {x} {y} {z}\n" for x, y, z in t) + "  endloop\n endfacet\n"
    for t in [[("nan", 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 0, 0), (0, 0, 1), (1, 0, 0)],
              [(0, 0, 0), (0, 1, 0), (0, 0, 1)], [(1, 0, 0), (0, 0, 1), (0, 1, 0)]]) + "endsolid x\n"
hostile_meshes = [
    ("binary STL declaring 10^9 triangles", "model/stl",
     b"\0" * 80 + struct.pack("<I", 10**9) + b"\0" * 100),
    ("binary PLY declaring 10^9 vertices and faces", "application/ply",
     ply_head.format(v=10**9, f=10**9).encode() + b"\0" * 120),
    ("binary PLY cut short (100 faces declared, 2 sent)", "application/ply",
     ply_head.format(v=4, f=100).encode() + corners + faces),
    ("ASCII STL with a NaN coordinate", "model/stl", nan_stl.encode()),
    ("ASCII PLY with an index out of range", "application/ply",
     b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
     b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
     b"0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
]
for name, content_type, data in hostile_meshes:
    status, body = request("POST", "/v1/jobs", data, {"Content-Type": content_type})
    expect(name, status, body, 400, "malformed_mesh")


def glb_parts(data):
    """A GLB's JSON and binary chunk."""
    json_length = int.from_bytes(data[12:16], "little")
    document = json.loads(data[20:20 + json_length])
    at = 20 + json_length
    bin_length = int.from_bytes(data[at:at + 4], "little")
    return document, data[at + 8:at + 8 + bin_length]


def glb_of(document, binary):
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    u32 = lambda v: v.to_bytes(4, "little")
    return (u32(0x46546C67) + u32(2) + u32(total) + u32(len(text)) + u32(0x4E4F534A) + text +
            u32(len(binary)) + u32(0x004E4942) + binary)


def finished(job_id, seconds=120):
    for _ in range(seconds * 10):
        status, body = request("GET", "/v1/jobs/" + job_id)
        answer = json.loads(body)
        if answer["status"] in ("succeeded", "failed", "cancelled"):
            return answer
        time.sleep(0.1)
    fail(f"job {job_id} did not finish in {seconds} s")


# Security III: one buffer copied per reference. 480 images naming one 4 MB bufferView
# were 480 copies in the server (std::bad_alloc under this cap: the server exited with
# 134) and in the worker and sphere.glb; now the bytes are held and written once.
document, binary = glb_parts(glb)
image = b"\x89PNG\r\n\x1a\n" + b"\0" * (4 << 20)
binary += b"\0" * (-len(binary) % 4)
document["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(image)})
binary += image
document["buffers"][0]["byteLength"] = len(binary)
view = len(document["bufferViews"]) - 1
document["images"] = [{"bufferView": view, "mimeType": "image/png"} for _ in range(480)]
status, body = request("POST", "/v1/jobs", glb_of(document, binary),
                       {"Content-Type": "model/gltf-binary"})
if status != 202:
    fail(f"480 images naming one 4 MB bufferView: {status} {body[:300]!r}")
answer = finished(json.loads(body)["id"])
if answer["status"] != "succeeded":
    fail("480 images naming one 4 MB bufferView: " + json.dumps(answer)[:300])
status, sphere = request("GET", answer["artifacts"]["sphere.glb"]["href"])
if status != 200 or len(sphere) > 6 << 20:
    fail(f"480 images naming one 4 MB bufferView: sphere.glb {status}, {len(sphere)} bytes")
print(f"480 images naming one 4 MB bufferView: mapped, sphere.glb {len(sphere) >> 10} KiB "
      "(the image once)")

# The same through a multipart .gltf whose 200 buffers all name one 4 MB part.
document, binary = glb_parts(glb)
binary += b"\0" * (4 << 20)
document["buffers"] = [{"uri": "scene.bin", "byteLength": len(binary)} for _ in range(200)]
parts = [("mesh", "scene.gltf", json.dumps(document).encode()), ("scene.bin", "scene.bin", binary)]
form = b"".join(f"--{boundary}\r\nContent-Disposition: form-data; name=\"{name}\"; "
                f"filename=\"{file}\"\r\nContent-Type: application/octet-stream\r\n\r\n"
                .encode() + data + b"\r\n" for name, file, data in parts) + f"--{boundary}--\r\n".encode()
status, body = request("POST", "/v1/jobs", form,
                       {"Content-Type": f"multipart/form-data; boundary={boundary}"})
if status != 202:
    fail(f".gltf with 200 buffers naming one 4 MB part: {status} {body[:300]!r}")
if finished(json.loads(body)["id"])["status"] != "succeeded":
    fail(".gltf with 200 buffers naming one 4 MB part: the job failed")
print(".gltf with 200 buffers naming one 4 MB part: mapped (the part read once)")

# Security III: attributes decoded per primitive before their counts were checked. 2,000
# three-vertex primitives naming one 4 MB MAT4 accessor as TEXCOORD_0, NORMAL and COLOR_0
# were 2,000 x 3 decodes (minutes of an intake thread, past its deadline and SIGTERM);
# now the accessor's count (not POSITION's) leaves it out before it is decoded, and the
# 2,000 separate triangles are refused as not closed, at once.
big_count = 65536
triangle = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
binary = triangle + b"\0" * (big_count * 64)
document = {
    "asset": {"version": "2.0"},
    "buffers": [{"byteLength": len(binary)}],
    "bufferViews": [{"buffer": 0, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 36, "byteLength": big_count * 64}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": big_count, "type": "MAT4"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "NORMAL": 1,
                                               "COLOR_0": 1}} for _ in range(2000)]}],
    "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
started = time.monotonic()
# Under prepare=parts the one triangle left once the copies are dropped is refused (the
# default, auto, would serve it as an envelope): the refusal shows nothing was decoded.
status, body = request("POST", "/v1/jobs?prepare=parts", glb_of(document, binary),
                       {"Content-Type": "model/gltf-binary"}, timeout=60)
took = time.monotonic() - started
expect("2,000 primitives naming one 4 MB MAT4 accessor as attributes", status, body, 422,
       "not_mappable")
if took > 10:
    fail(f"2,000 primitives naming one 4 MB MAT4 accessor: answered after {took:.1f} s")
print(f"  answered in {took:.2f} s")

# 200 requests at once, each a 60,000-deep document: the threads refuse them in turn.
errors = []


def burst():
    try:
        s, _ = request("POST", "/v1/jobs", deep_gltf, {"Content-Type": "model/gltf+json"})
        if s not in (400, 503):
            errors.append(s)
    except OSError as e:
        errors.append(str(e))


threads = [threading.Thread(target=burst) for _ in range(200)]
for t in threads:
    t.start()
for t in threads:
    t.join()
if errors:
    fail(f"burst of deep documents: {errors[:5]}")
print("200 deep documents at once: each refused")

stop.set()
prober.join()
trickler.join()
if probe_failures:
    fail(f"/healthz on the health port failed: {probe_failures[:3]}")
if worst[0] >= 2:
    fail(f"/healthz took {worst[0]:.2f} s during the attacks")
print(f"/healthz on the health port: always 200, at most {worst[0]:.3f} s")
status, body = request("POST", "/v1/jobs", glb, {"Content-Type": "model/gltf-binary"})
if status != 202:
    fail(f"a good job after the attacks: {status}")
job = json.loads(body)["id"]
for _ in range(300):
    status, body = request("GET", "/v1/jobs/" + job)
    if json.loads(body)["status"] in ("succeeded", "failed", "cancelled"):
        break
    time.sleep(0.1)
if json.loads(body)["status"] != "succeeded":
    fail("a good job after the attacks: " + body.decode()[:300])
print("a good job after the attacks: succeeded")
