#!/usr/bin/env python3
"""Assembles a third reach set (/work/reach-set3, session 36) from bare git mirrors (the
fetch tool: /work/.mirror/OWNER+NAME/repo), like assemble-set2.py: each chosen mesh file plus
the files a .gltf names (buffers, images), and MANIFEST.tsv (file kind source path bytes repo
commit licence). Skipped: files over 30 MB, blobs absent from the snapshot, Git LFS pointers,
and a blob already taken (same git hash: e.g. godot's mono/ copies of 3d/ demos). A source
with more than `cap` matches keeps every k-th (k = ceil(n/cap)) of the sorted list.
Usage: python3 bench/reach/assemble-set3.py; then JOBS=1 PREPARE=auto COMPARE=none
bench/reach/run.sh build/cli/spheremap /work/reach-set3"""
import json, math, os, re, subprocess
M = "/work/.mirror"
OUT = "/work/reach-set3"
EXT = r"\.(glb|gltf|obj|off|stl|ply)$"
REPOS = {  # repo -> (short name, licence as stated, include regex, cap)
 "KhronosGroup/glTF-Validator": ("gltf-validator", "Apache-2.0 (repo LICENSE)", r"^test/.*\.(gltf|glb)$", 95),
 "openscad/openscad": ("openscad", "GPL-2.0-or-later (repo COPYING); test and example files without notes of their own",
   r"^(tests|examples)/.*" + EXT, 60),
 "godotengine/godot-demo-projects": ("godot-demos", "MIT (repo LICENSE.md); some assets credit Poly Haven (CC0) or others in their folders",
   r".*" + EXT, 60),
 "sgsellan/gpytoolbox": ("gpytoolbox", "MIT (repo LICENSE.MIT; LICENSE.GPL for GPL-linked parts); test meshes without notes (Stanford bunny, armadillo, spot, ...)",
   r"^test/unit_tests_data/.*" + EXT, 60),
 "nmwsharp/geometry-central": ("geometry-central", "MIT (repo LICENSE); test assets without notes", r"^test/assets/.*" + EXT, 60),
 "nschloe/meshio": ("meshio", "MIT (repo LICENSE.txt)", r"^tests/meshes/.*" + EXT, 60),
}
def git(repo, *args, text=True):
    return subprocess.run(["git", "--git-dir", f"{M}/{repo.replace('/', '+')}/repo", *args],
                          capture_output=True, text=text, check=True).stdout
rows, seen = [], set()
for repo, (short, lic, inc, cap) in REPOS.items():
    commit = git(repo, "rev-parse", "HEAD").strip()
    sizes, blobs = {}, {}
    for line in git(repo, "ls-tree", "-r", "-l", "HEAD").splitlines():
        meta, path = line.split("\t", 1)
        _, _, blob, size = meta.split()
        sizes[path] = int(size) if size.isdigit() else None
        blobs[path] = blob
    def copy(path):
        data = git(repo, "show", f"HEAD:{path}", text=False)
        dst = f"{OUT}/{short}/{path}"
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        open(dst, "wb").write(data)
        return data
    chosen = [p for p in sorted(sizes) if re.search(inc, p, re.I)]
    k = math.ceil(len(chosen) / cap)
    for path in chosen[::k]:
        size = sizes[path]
        if size is None or size > 30e6 or blobs[path] in seen: continue
        try: data = copy(path)
        except subprocess.CalledProcessError: continue
        if data.startswith(b"version https://git-lfs"): os.remove(f"{OUT}/{short}/{path}"); continue
        seen.add(blobs[path])
        if path.endswith(".gltf"):
            try: doc = json.loads(data)
            except ValueError: doc = {}
            items = (doc.get("buffers") or []) + (doc.get("images") or []) if isinstance(doc, dict) else []
            for item in items if isinstance(items, list) else []:
                uri = item.get("uri", "") if isinstance(item, dict) else ""
                if isinstance(uri, str) and uri and not uri.startswith("data:"):
                    dep = os.path.normpath(os.path.join(os.path.dirname(path), uri.replace("%20", " ")))
                    if sizes.get(dep): copy(dep)
        first, _, rest = path.partition("/")
        rows.append([f"{short}/{path}", short, first, rest, str(len(data)), repo, commit, lic])
with open(f"{OUT}/MANIFEST.tsv", "w") as f:
    f.write("file\tkind\tsource\tpath\tbytes\trepo\tcommit\tlicence\n")
    for r in rows: f.write("\t".join(r) + "\n")
import collections
print(len(rows), collections.Counter(r[1] for r in rows))
