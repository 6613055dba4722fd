#!/usr/bin/env bash
# Builds a libFuzzer target with clang (ASan + UBSan, in build-sanitized/:
# scripts/build-sanitized.sh) and runs it for SECONDS (default 60) from a seed corpus taken from the shared corpus (or, without it, from examples/): GLB and Draco GLB files for
# gltf_fuzzer (with truncated, garbage and external-URI files like the hostile-file
# tests), small OBJ files for mesh_text_fuzzer, option sets for options_fuzzer; STL, PLY
# and .drc files written here (a tetrahedron in every encoding) for mesh_binary_fuzzer.
# Crashes land in
# build-sanitized/crashes/; turn each into a regression test.
# Several targets (comma-separated) are built in one go and run side by side, as many at
# a time as there are cores (a libFuzzer process uses one), each for SECONDS; their
# output is printed target by target, and the run fails if any of them found a crash.
# Usage: tests/fuzz/run.sh [SECONDS] [TARGET[,TARGET...]] [CORPUS_DIR]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:-60}
IFS=, read -r -a targets <<< "${2:-gltf_fuzzer}"
corpus=${3:-../shared/meshes}
# A clone without the shared corpus seeds from the meshes it ships (examples/).
[ -d "$corpus" ] || corpus=examples
# The fuzzers are built in build-sanitized/, with the sanitizer pass's tests if it ran.
scripts/build-sanitized.sh "${targets[@]}" > /dev/null
mkdir -p build-sanitized/crashes build-sanitized/logs

# make_seeds TARGET: writes the seed corpus of TARGET into build-sanitized/seeds/TARGET.
make_seeds() {
  local target=$1
  local seeds=build-sanitized/seeds/$target
  mkdir -p "$seeds"
  local pattern='*.glb'
  [ "$target" = mesh_text_fuzzer ] && pattern='*.obj'
  if [ "$target" = request_fuzzer ]; then  # submissions as the tests send them
    # find | head under pipefail fails when find does (a missing folder): read it all.
    local glb
    glb=$(find "$corpus" -maxdepth 1 -name '*.glb' -size -40k 2> /dev/null | sort | sed -n 1p || true)
    { printf '\000draco=true&layout=welded\n'; [ -n "$glb" ] && cat "$glb"; } > "$seeds/glb"
    { printf '\002outputs=remesh\n'; [ -n "$glb" ] && cat "$glb";
      printf '\n--\n{"quality": "fast", "largest_component": true}'; } > "$seeds/multipart"
    printf '\002mesh=0\n{"asset":{"version":"2.0"},"buffers":[{"uri":"a%%20b.bin","byteLength":4}]}\n--\na b.bin\nABCD' > "$seeds/gltf_parts"
    printf '\001\n{"asset":{"version":"2.0"},"extensionsRequired":["EXT_meshopt_compression"],"buffers":[{"byteLength":8,"extensions":{"EXT_meshopt_compression":{"fallback":true}}}]}' > "$seeds/meshopt"
  elif [ "$target" = connection_fuzzer ]; then  # requests as clients send them
    printf 'GET /v1/jobs/0123456789abcdef0123456789abcdef HTTP/1.1\r\nHost: x\r\n\r\nGET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n' > "$seeds/pipelined"
    printf 'POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: model/gltf-binary\r\nContent-Length: 8\r\n\r\nglTFglTF' > "$seeds/post"
    printf 'POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: multipart/form-data; boundary=b\r\nContent-Length: 98\r\n\r\n--b\r\nContent-Disposition: form-data; name="mesh"; filename="m.glb"\r\n\r\nglTF\r\n--b--\r\n' > "$seeds/multipart"
    printf 'POST /v1/jobs HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n4\r\nglTF\r\n0\r\n\r\n' > "$seeds/chunked"
    printf 'GET /v1/openapi.yaml HTTP/1.1\r\nHost: x\r\nRange: bytes=0-1,2-3\r\nX-a: b\r\nX-b: c\r\n\r\n' > "$seeds/headers"
  elif [ "$target" = mesh_binary_fuzzer ]; then  # a tetrahedron as STL, PLY (every encoding), .drc
    python3 - "$seeds" <<'PY'
import struct, sys
d = sys.argv[1]
v = [(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)]
f = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
for name, header in (("binary.stl", b"tetrahedron"), ("solid_header.stl", b"solid tet")):
    out = header.ljust(80, b" ") + struct.pack("<I", len(f))
    for t in f:
        out += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v[i]) for i in t) + b"\0\0"
    open(f"{d}/{name}", "wb").write(out)
text = "solid tet\n" + "".join(
    "facet normal 0 0 0\nouter loop\n" + "".join("vertex %g %g %g\n" % v[i] for i in t) +
    "endloop\nendfacet\n" for t in f) + "endsolid tet\n"
open(f"{d}/ascii.stl", "w").write(text)
for enc, fmt in (("ascii", None), ("binary_little_endian", "<"), ("binary_big_endian", ">")):
    head = (f"ply\nformat {enc} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nproperty uchar red\nelement face 4\n"
            "property list uchar int vertex_indices\nend_header\n").encode()
    if fmt is None:
        body = "".join("%g %g %g 7\n" % p for p in v) + "".join("3 %d %d %d\n" % t for t in f)
        open(f"{d}/{enc}.ply", "wb").write(head + body.encode())
    else:
        body = b"".join(struct.pack(fmt + "3fB", *p, 7) for p in v)
        body += b"".join(struct.pack(fmt + "B3i", 3, *t) for t in f)
        open(f"{d}/{enc}.ply", "wb").write(head + body)
# The same tetrahedron as raw Draco files (draco_encoder's .drc), sequential (unquantized)
# and edgebreaker (14-bit positions), as Debian's libdraco 1.5.5 encodes them.
for name, hex_bytes in (
        ("sequential.drc",
         "445241434f02020100000004040100010200030100020301030201010009030000000000803f0000803f"
         "0000803f0000803f000080bf000080bf000080bf0000803f000080bf000080bf000080bf0000803f"),
        ("edgebreaker.drc",
         "445241434f02020101000000040400030000012f01011001ff0000010009030000020101010003030120"
         "0120030010840c2d0000000000ff3f0000000080bf000080bf000080bf000000400e")):
    open(f"{d}/{name}", "wb").write(bytes.fromhex(hex_bytes))
PY
  elif [ "$target" = options_fuzzer ]; then  # the options the tests and the README use
    printf '%s' '{"draco": true, "draco_position_bits": 16, "layout": "welded"}' > "$seeds/a.json"
    printf '%s' '{"method": "paper", "max_iterations": 200, "time_limit_seconds": 0.5}' > "$seeds/b.json"
    printf '%s' '{"outputs": ["remesh", "uv", "morph"], "resolution": 64, "mesh": "cow"}' > "$seeds/c.json"
    printf '%s' 'outputs=remesh,uv&resolution=32&draco=true&attempts=3&alpha=0.5' > "$seeds/d.txt"
  else
    find "$corpus" -name "$pattern" -size -200k -exec cp {} "$seeds/" \; 2> /dev/null || true
  fi
  if [ "$target" = mesh_text_fuzzer ]; then  # an MNI obj surface: a tetrahedron
    printf 'P 0.3 0.3 0.4 10 1 4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n\n0 0 1\n0 0 1\n0 0 1\n0 0 1\n\n4\n0 1 1 1 1\n\n3 6 9 12\n\n0 2 1 0 1 3 1 2 3 0 3 2\n' > "$seeds/mni.obj"
  fi
  if [ "$target" = gltf_fuzzer ]; then  # the shapes of the hostile-file tests, as files
    local small
    small=$(ls "$seeds"/*.glb 2> /dev/null | sed -n 1p || true)
    if [ -n "$small" ]; then
      for cut in 12 20 100 1000; do head -c $cut "$small" > "$seeds/truncated_$cut.glb"; done
      { printf 'glTF'; head -c 200 /dev/urandom; } > "$seeds/garbage.glb"
    fi
    printf '%s' '{"asset":{"version":"2.0"},"buffers":[{"uri":"file:///etc/passwd","byteLength":10}],"bufferViews":[{"buffer":0,"byteLength":10}],"accessors":[{"bufferView":0,"componentType":5126,"count":1000000000,"type":"VEC3"}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}' > "$seeds/external_uri.gltf"
    # glTF 1.0 (read through its 2.0 upgrade): ids for indices, a node of two meshes.
    printf '%s' '{"asset":{"version":"1.0"},"buffers":{"b":{"byteLength":42,"uri":"data:;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA"}},"bufferViews":{"v":{"buffer":"b","byteOffset":0,"byteLength":36},"i":{"buffer":"b","byteOffset":36,"byteLength":6}},"accessors":{"p":{"bufferView":"v","byteOffset":0,"byteStride":12,"componentType":5126,"count":3,"type":"VEC3"},"x":{"bufferView":"i","byteOffset":0,"componentType":5123,"count":3,"type":"SCALAR"}},"meshes":{"m":{"primitives":[{"attributes":{"POSITION":"p"},"indices":"x","material":"c"}]}},"materials":{"c":{"values":{"diffuse":[1,0,0,1]}}},"nodes":{"n":{"meshes":["m","m"],"matrix":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]}},"scenes":{"s":{"nodes":["n"]}},"scene":"s"}' > "$seeds/gltf1.gltf"
  fi
}

for target in "${targets[@]}"; do make_seeds "$target"; done
# Run at most nproc fuzzers at a time; each one's output goes to its log.
pids=() names=() status=0
for target in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
  "build-sanitized/tests/fuzz/$target" -max_total_time="$seconds" -max_len=4000000 -rss_limit_mb=2048 \
    -artifact_prefix=build-sanitized/crashes/ -print_final_stats=1 "build-sanitized/seeds/$target" \
    > "build-sanitized/logs/$target.log" 2>&1 &
  pids+=($!) names+=("$target")
done
for i in "${!pids[@]}"; do
  result=0
  wait "${pids[$i]}" || result=$?
  echo "== ${names[$i]} (exit $result)"
  tail -25 "build-sanitized/logs/${names[$i]}.log"
  [ $result -eq 0 ] || status=1
done
exit $status
