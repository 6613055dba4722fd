"""Slow and non-reading clients against a running spheremap server (issue 31, item 7;
tests/attack/slow_clients.sh starts it under a memory cap). 1,000 connections from four
non-loopback addresses (127.0.0.2-5), a third of each kind, reconnecting whenever the
server drops them, for HOLD seconds:
  - slow headers: a request line, then one header byte every 2 s;
  - slow bodies: a POST head declaring 1 MB, then one body byte every 2 s;
  - never-reading downloads: GET of a multi-MB artifact with a 4 KiB receive buffer,
    never read.
Meanwhile GET /healthz on the API port (from 127.0.0.1) every 100 ms must answer 200,
each within 2 s. Prints /healthz's latency (max, p99) and the server's threads and
resident memory (sampled from /proc) during the attack. Exits 1 on a failure.
Usage: slow_clients.py API_URL SERVER_PID GLB_FILE [HOLD_SECONDS [CONNECTIONS]]"""
import http.client
import json
import os
import selectors
import socket
import sys
import threading
import time
import urllib.parse

api, server_pid, glb_path = sys.argv[1:4]
hold = float(sys.argv[4]) if len(sys.argv) > 4 else 20
host, port = urllib.parse.urlsplit(api).hostname, urllib.parse.urlsplit(api).port
glb = open(glb_path, "rb").read()
addresses = ["127.0.0.2", "127.0.0.3", "127.0.0.4", "127.0.0.5"]
total = int(sys.argv[5]) if len(sys.argv) > 5 else 1000
# Slow headers, slow bodies, never-reading downloads: a third each.
per_kind = [total - 2 * (total // 3), total // 3, total // 3]


def fail(message):
    print("FAIL: " + message, flush=True)
    os._exit(1)


def request(method, path, body=None, headers=None, timeout=30):
    connection = http.client.HTTPConnection(host, port, timeout=timeout)
    connection.request(method, path, body=body, headers=headers or {})
    response = connection.getresponse()
    data = response.read()
    connection.close()
    return response.status, data


def glb_with_image(data, image_bytes):
    """The GLB with one (opaque) PNG image of `image_bytes` added: a large sphere.glb."""
    json_length = int.from_bytes(data[12:16], "little")
    document = json.loads(data[20:20 + json_length])
    at = 20 + json_length
    binary = data[at + 8:at + 8 + int.from_bytes(data[at:at + 4], "little")]
    image = b"\x89PNG\r\n\x1a\n" + b"\0" * image_bytes
    binary += b"\0" * (-len(binary) % 4)
    document["bufferViews"].append({"buffer": 0, "byteOffset": len(binary),
                                    "byteLength": len(image)})
    binary += image
    document["buffers"][0]["byteLength"] = len(binary)
    document["images"] = [{"bufferView": len(document["bufferViews"]) - 1,
                           "mimeType": "image/png"}]
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    u32 = lambda v: v.to_bytes(4, "little")
    total = 12 + 8 + len(text) + 8 + len(binary)
    return (u32(0x46546C67) + u32(2) + u32(total) + u32(len(text)) + u32(0x4E4F534A) + text +
            u32(len(binary)) + u32(0x004E4942) + binary)


def run_job(body):
    status, answer = request("POST", "/v1/jobs", body, {"Content-Type": "model/gltf-binary"})
    if status != 202:
        fail(f"job: {status} {answer[:300]!r}")
    job = json.loads(answer)["id"]
    for _ in range(1200):
        status, answer = request("GET", "/v1/jobs/" + job)
        state = json.loads(answer)
        if state["status"] in ("succeeded", "failed", "cancelled"):
            return state
        time.sleep(0.1)
    fail(f"job {job} did not finish")


# A large artifact to download: sphere.glb carries the input's 6 MB image.
state = run_job(glb_with_image(glb, 6 << 20))
if state["status"] != "succeeded":
    fail("the large job: " + json.dumps(state)[:300])
artifact = state["artifacts"]["sphere.glb"]["href"]
status, data = request("GET", artifact)
if status != 200 or len(data) < 6 << 20:
    fail(f"the large artifact: {status}, {len(data)} bytes")
print(f"large artifact: {artifact}, {len(data) >> 20} MiB", flush=True)

# The prober: /healthz on the API port, every 100 ms, each answer within 2 s.
latencies, failures = [], []
stop = threading.Event()


def probe():
    while not stop.is_set():
        start = time.monotonic()
        try:
            c = http.client.HTTPConnection(host, port, timeout=2)
            c.request("GET", "/healthz")
            response = c.getresponse()
            response.read()
            if response.status != 200:
                failures.append(f"status {response.status}")
            c.close()
        except OSError as e:
            failures.append(f"{type(e).__name__}: {e}")
        took = time.monotonic() - start
        latencies.append(took)
        if took >= 2:
            failures.append(f"{took:.2f} s")
        time.sleep(0.1)


# The server's threads and resident memory, once a second.
samples = []


def sample():
    while not stop.is_set():
        try:
            status = open(f"/proc/{server_pid}/status").read()
            fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
            samples.append((int(fields["Threads"]), int(fields["VmRSS"].split()[0]) >> 10))
        except OSError:
            pass
        time.sleep(1)


HEAD = b"GET /healthz HTTP/1.1\r\nHost: x\r\n"
BODY_HEAD = (b"POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\n"
             b"Content-Length: 1000000\r\n\r\nglTF")
DOWNLOAD = f"GET {artifact} HTTP/1.1\r\nHost: x\r\n\r\n".encode()


class Client:
    def __init__(self, kind, address):
        self.kind, self.address, self.sock = kind, address, None
        self.sent_at = 0.0

    def connect(self, selector):
        s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if self.kind == "download":
            s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        s.bind((self.address, 0))
        s.setblocking(False)
        try:
            s.connect((host, port))
        except BlockingIOError:
            pass
        self.sock = s
        self.started = False
        selector.register(s, selectors.EVENT_WRITE, self)

    def on_event(self, selector, events):
        if not self.started and events & selectors.EVENT_WRITE:
            if self.sock.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR):
                return self.reconnect(selector)
            self.started = True
            first = {"headers": HEAD, "body": BODY_HEAD, "download": DOWNLOAD}[self.kind]
            try:
                self.sock.send(first)
            except OSError:
                return self.reconnect(selector)
            self.sent_at = time.monotonic()
            # Tricklers watch for the server's answer or close; downloads never read.
            if self.kind == "download":
                selector.unregister(self.sock)
            else:
                selector.modify(self.sock, selectors.EVENT_READ, self)
            return
        if events & selectors.EVENT_READ and self.kind != "download":
            try:
                data = self.sock.recv(4096)
            except OSError:
                data = b""
            if not data:
                return self.reconnect(selector)
            counts[self.kind + " answered"] = counts.get(self.kind + " answered", 0) + 1

    def trickle(self, selector, now):
        if self.started and self.kind != "download" and now - self.sent_at >= 2:
            try:
                self.sock.send(b"X" if self.kind == "headers" else b"\0")
                self.sent_at = now
            except OSError:
                self.reconnect(selector)

    def reconnect(self, selector):
        counts[self.kind + " reconnects"] = counts.get(self.kind + " reconnects", 0) + 1
        try:
            selector.unregister(self.sock)
        except (KeyError, ValueError):
            pass
        self.sock.close()
        self.connect(selector)


counts = {}
prober = threading.Thread(target=probe)
sampler = threading.Thread(target=sample)
selector = selectors.DefaultSelector()
clients = []
for kind, count in zip(("headers", "body", "download"), per_kind):
    for k in range(count):
        clients.append(Client(kind, addresses[k % len(addresses)]))
for c in clients:
    c.connect(selector)
prober.start()
sampler.start()
started = time.monotonic()
while time.monotonic() - started < hold:
    for key, events in selector.select(timeout=0.2):
        key.data.on_event(selector, events)
    now = time.monotonic()
    for c in clients:
        c.trickle(selector, now)
stop.set()
prober.join()
sampler.join()
held = sum(1 for c in clients if c.started)
for c in clients:
    c.sock.close()

latencies.sort()
p99 = latencies[min(len(latencies) - 1, int(len(latencies) * 0.99))] if latencies else 0
print(f"{total} slow clients from {len(addresses)} addresses for {hold:.0f} s "
      f"({held} connected at the end; {counts}):", flush=True)
print(f"  /healthz on the API port: {len(latencies)} probes, max {latencies[-1]:.3f} s, "
      f"p99 {p99:.3f} s", flush=True)
if samples:
    print(f"  server: threads max {max(t for t, _ in samples)}, "
          f"RSS max {max(r for _, r in samples)} MiB", flush=True)
if failures:
    fail(f"/healthz during the attack: {len(failures)} failed: {failures[:5]}")

state = run_job(glb)
if state["status"] != "succeeded":
    fail("a good job after the attack: " + json.dumps(state)[:300])
print("a good job after the attack: succeeded", flush=True)
