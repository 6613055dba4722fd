#!/usr/bin/env python3
"""Assembles a third reach set (/work/reach-set3, session 36) from bare git mirrors (the
fetch tool: /work/.mirror/OWNER+NAME/repo), like assemble-set2.py: each chosen mesh file plus
the files a .gltf names (buffers, images), and MANIFEST.tsv (file kind source path bytes repo
commit licence). Skipped: files over 30 MB, blobs absent from the snapshot, Git LFS pointers,
and a blob already taken (same git hash: e.g. godot's mono/ copies of 3d/ demos). A source
with more than `cap` matches keeps every k-th (k = ceil(n/cap)) of the sorted list.
Usage: python3 bench/reach/assemble-set3.py; then JOBS=1 PREPARE=auto COMPARE=none
bench/reach/run.sh build/cli/spheremap /work/reach-set3
The selection itself is reach_select.py (shared with the other set scripts)."""
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
from reach_select import Source, assemble
assemble([Source(repo, short, lic, inc, cap=cap) for repo, (short, lic, inc, cap) in REPOS.items()],
         OUT, max_bytes=30e6, dedup=True, ignore_case=True)
