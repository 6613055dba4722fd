#!/usr/bin/env python3
"""Assembles a fifth reach set (/work/reach-set5, session 39) from bare git mirrors of
repositories no earlier set used (reach_select.py: the selection, shared with sets 2-4): a
viewer's test data (f3d), physics and robot models (bullet3's data, example-robot-data:
CAD exports, collision hulls, URDF meshes) and a glTF pipeline's test files (gltf-pipeline).
Per source, the sorted .glb .gltf .obj .off .stl .ply .drc files under the listed folders,
every k-th over a cap of 50; skipped: files over 30 MB, blobs absent from the snapshot, Git
LFS pointers, a blob already taken. Writes /work/reach-set5/MANIFEST.tsv (committed as
bench/reach/MANIFEST-set5.tsv).
Usage: python3 bench/reach/assemble-set5.py; then PREPARE=auto COMPARE=none
bench/reach/run.sh build/cli/spheremap /work/reach-set5"""
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("f3d-app/f3d", "f3d", "BSD-3-Clause (repo LICENSE.md); testing/data without notes of their own",
           r"^testing/data/.*" + EXT, cap=50),
    Source("bulletphysics/bullet3", "bullet3",
           "zlib (repo LICENSE.txt); data/ models (robots, kitchens) without notes of their own",
           r"^data/.*" + EXT, cap=50),
    Source("CesiumGS/gltf-pipeline", "gltf-pipeline",
           "Apache-2.0 (repo LICENSE.md); specs/data are Khronos sample models (their own CC-BY/CC0 terms)",
           r"^specs/data/.*" + EXT, cap=50),
    Source("Gepetto/example-robot-data", "example-robot-data",
           "BSD-3-Clause (repo LICENSE); robot meshes from their makers' descriptions",
           r"^robots/.*" + EXT, cap=50),
]

assemble(SOURCES, "/work/reach-set5", max_bytes=30e6, dedup=True, ignore_case=True)
