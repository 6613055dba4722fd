#!/usr/bin/env bash
# Assembles the reach set: a deterministic selection of real public mesh files (.glb .gltf
# .obj .off .stl .ply) taken from bare git mirrors, grouped by source kind. Per source: the
# sorted list of usable files (not Git LFS pointers, at most 30 MB, .gltf only when its
# external buffers are in the repository too), and when it has more than 60, every k-th one
# (k = ceil(n/60)); blobs absent from a mirror are skipped. Writes OUT/<kind>/<source>/<path in repo> and OUT/MANIFEST.tsv
# (kind, source repo, commit, path, bytes). The files are not committed: see MANIFEST.md.
# Usage: bench/reach/assemble.sh [MIRRORS=/work/.mirror] [OUT=/work/reach-set]
set -euo pipefail
mirrors=${1:-/work/.mirror}
out=${2:-/work/reach-set}
# Starts afresh, but only removes a folder this script made (or an empty one).
if [ -d "$out" ] && [ -n "$(ls -A "$out")" ] && [ ! -f "$out/MANIFEST.tsv" ]; then
  echo "$out is not empty and holds no MANIFEST.tsv: not removing it" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
python3 - "$mirrors" "$out" << 'EOF'
import json, math, os, re, subprocess, sys
from posixpath import dirname, join, normpath
mirrors, out = sys.argv[1:3]
kinds = {  # source (owner+name) -> kind
    "KenneyNL+Starter-Kit-3D-Platformer": "game-kits",
    "KenneyNL+Starter-Kit-City-Builder": "game-kits",
    "KenneyNL+Starter-Kit-FPS": "game-kits",
    "KenneyNL+Starter-Kit-Racing": "game-kits",
    "assimp+assimp": "engine-and-library-test-data",
    "mikedh+trimesh": "engine-and-library-test-data",
    "cnr-isti-vclab+meshlab": "engine-and-library-test-data",
    "prusa3d+PrusaSlicer": "slicer-and-printing",
    "slic3r+Slic3r": "slicer-and-printing",
    "Ultimaker+Uranium": "slicer-and-printing",
    "alecjacobson+common-3d-test-models": "scans-and-classic-test-meshes",
    "libigl+libigl-tutorial-data": "scans-and-classic-test-meshes",
}
exts = (".glb", ".gltf", ".obj", ".off", ".stl", ".ply")
limit, per_source = 30_000_000, 60
def git(gd, *args):
    return subprocess.run(["git", "-C", gd, *args], check=True, capture_output=True).stdout
manifest = [("kind", "source", "commit", "path", "bytes")]
for source, kind in kinds.items():
    gd = join(mirrors, source, "repo")
    if os.path.isdir(join(gd, ".git")):
        gd = join(gd, ".git")
    commit = git(gd, "rev-parse", "HEAD").decode().strip()
    blobs = {}  # path -> size, for every blob of the tree
    for line in git(gd, "ls-tree", "-r", "-l", "-z", "HEAD").split(b"\0"):
        if line:
            meta, path = line.decode().split("\t", 1)
            _, typ, _, size = meta.split()
            if typ == "blob" and size.isdigit():  # size "BAD": blob absent from the mirror
                blobs[path] = int(size)
    def show(path):
        return git(gd, "show", f"HEAD:{path}")
    usable = []  # (path, extra files it needs)
    for path in sorted(p for p in blobs if p.lower().endswith(exts)):
        if blobs[path] > limit:
            continue
        data = show(path)
        if data.startswith(b"version https://git-lfs"):
            continue
        extra = []
        if path.lower().endswith(".gltf"):  # needs its external buffers (not images)
            try:
                uris = [b.get("uri", "") for b in json.loads(data).get("buffers", [])]
            except Exception:
                uris = []  # broken JSON: keep it, the reader must say so
            extra = [normpath(join(dirname(path), u)) for u in uris if u and not u.startswith("data:")]
            if any(e not in blobs for e in extra):
                continue
        usable.append((path, extra))
    step = math.ceil(len(usable) / per_source) if len(usable) > per_source else 1
    for path, extra in usable[::step]:
        for p in [path] + extra:
            dest = join(out, kind, source, p)
            os.makedirs(dirname(dest), exist_ok=True)
            with open(dest, "wb") as f:
                f.write(show(p))
        manifest.append((kind, source, commit, path, str(blobs[path])))
    print(f"{source}: {len(usable)} usable, took {len(usable[::step])} (every {step})", file=sys.stderr)
with open(join(out, "MANIFEST.tsv"), "w") as f:
    f.writelines("\t".join(r) + "\n" for r in manifest)
rows = manifest[1:]
print(f"{len(rows)} files, {sum(r[3].lower().endswith(('.stl', '.ply')) for r in rows)} STL/PLY", file=sys.stderr)
EOF
