#!/usr/bin/env bash
# api/openapi.yaml is a valid OpenAPI 3.1 document (npm @redocly/cli lint: no errors) and
# matches the routes: every documented operation is answered by the real server (not the
# "no route" 404), and every /v1 route in api/routes.cpp is documented.
# Exit 77 (skipped) without npm.
set -uo pipefail
spheremap=$1 make_meshes=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
. "$here/../start_server.sh"
. "$here/../npm_packages.sh"
fail() { echo "FAIL: $*"; exit 1; }
need_npm_packages "$here" .bin/redocly
work=$(mktemp -d)
trap 'kill $server 2> /dev/null; wait $server 2> /dev/null; rm -rf "$work"' EXIT
"$here/node_modules/.bin/redocly" lint "$root/api/openapi.yaml" --format=stylish > "$work/lint.txt" 2>&1 ||
  { cat "$work/lint.txt"; fail "redocly lint found errors"; }
grep -E '^\s+[0-9]+:[0-9]+\s+warning' "$work/lint.txt" || true
"$here/node_modules/.bin/redocly" bundle "$root/api/openapi.yaml" --ext json -o "$work/openapi.json" > /dev/null 2>&1 ||
  fail "redocly bundle"

start_server "$work/server.log" --workers 1
"$make_meshes" "$work" > /dev/null || fail "make_test_meshes"
python3 - "$work/openapi.json" "$root/api/routes.cpp" "$url" "$work/icosphere2.glb" <<'PY' || exit 1
import json, re, sys, time, urllib.request, urllib.error
doc, routes_cpp, base, mesh = sys.argv[1:]
spec = json.load(open(doc))
documented = {(m.upper(), p) for p, ops in spec["paths"].items() for m in ops if m in ("get", "post", "delete")}

# The routes the server installs, from api/routes.cpp, in the document's path syntax.
source = open(routes_cpp).read()
installed = set()
for method, expr in re.findall(r'http\.(Get|Post|Delete)\(\s*((?:std::string\()?"[^;]*?)(?:,\s*\n?\s*(?:guarded|\[))', source):
    path = "".join(re.findall(r'"([^"]*)"', expr.replace("kJobId", '"{id}"')))
    path = path.replace("([A-Za-z0-9_.-]+)", "{name}")
    if path.startswith("/v1/") or path in ("/healthz", "/readyz", "/metrics"):
        installed.add((method.upper(), path))
missing = installed - documented
if missing: sys.exit(f"FAIL: routes not in openapi.yaml: {sorted(missing)}")
unserved = documented - installed
if unserved: sys.exit(f"FAIL: documented but not in routes.cpp: {sorted(unserved)}")

def call(method, path, body=None, headers={}):
    request = urllib.request.Request(base + path, data=body, method=method, headers=headers)
    try:
        with urllib.request.urlopen(request, timeout=60) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        return e.code, e.read()

status, body = call("POST", "/v1/jobs", open(mesh, "rb").read(), {"Content-Type": "model/gltf-binary"})
job = json.loads(body)["id"]
for _ in range(600):
    if json.loads(call("GET", f"/v1/jobs/{job}")[1])["status"] not in ("queued", "running"): break
    time.sleep(0.05)
for method, path in sorted(documented, key=lambda op: (op[0] == "DELETE", op[1])):
    concrete = path.replace("{id}", job).replace("{name}", "metrics.json")
    body, headers = None, {}
    if method == "POST":
        body, headers = open(mesh, "rb").read(), {"Content-Type": "model/gltf-binary"}
    status, answer = call(method, concrete, body, headers)
    if status == 404 and b"no route for" in answer:
        sys.exit(f"FAIL: {method} {path} is documented but the server has no route")
    print(f"{method} {path}: {status}")
print(f"openapi: {len(documented)} operations documented, linted and served")
PY
