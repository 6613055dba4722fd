#!/usr/bin/env python3
"""Assembles a fourth reach set (/work/reach-set4, session 37) from bare git mirrors of
repositories no earlier set used (reach_select.py: the selection, shared with set 2 and 3).
Per source, the sorted .glb .gltf .obj .off .stl .ply .drc files under the listed folders,
every k-th over a cap of 50; skipped: files over 30 MB, blobs absent from the snapshot, Git
LFS pointers, a blob already taken. Writes /work/reach-set4/MANIFEST.tsv (committed as
bench/reach/MANIFEST-set4.tsv).
Usage: python3 bench/reach/assemble-set4.py; then PREPARE=auto COMPARE=none
bench/reach/run.sh build/cli/spheremap /work/reach-set4"""
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("kovacsv/Online3DViewer", "online3dviewer",
           "MIT (repo LICENSE.md); test/testfiles/gltf samples carry Khronos READMEs/LICENSE (MIT, CC-BY)",
           r"^(test/testfiles|website/assets/models)/.*" + EXT, cap=50),
    Source("syoyo/tinyobjloader", "tinyobjloader", "MIT (repo LICENSE); test models without notes of their own",
           r"^(models|tests)/.*" + EXT, cap=50),
    Source("syoyo/tinygltf", "tinygltf", "MIT (repo LICENSE); test models without notes of their own",
           r"^(models|tests)/.*" + EXT, cap=50),
    Source("ssloy/tinyrenderer", "tinyrenderer",
           "zlib-style (repo LICENSE.txt); obj/*/readme.txt credit the models (african_head (c) 2007 Vidar Rapp, ...)",
           r"^obj/.*" + EXT, cap=50),
    Source("mmatl/pyrender", "pyrender", "MIT (repo LICENSE); example and test models without notes of their own",
           r"^(examples/models|tests/data)/.*" + EXT, cap=50),
    Source("jkuhlmann/cgltf", "cgltf", "MIT (repo LICENSE); fuzz seed files", r"^fuzz/data/.*" + EXT, cap=50),
    Source("donmccurdy/glTF-Transform", "gltf-transform", "MIT (repo LICENSE.md); test fixtures without notes of their own",
           r"^packages/.*" + EXT, cap=50),
]

assemble(SOURCES, "/work/reach-set4", max_bytes=30e6, dedup=True, ignore_case=True)
