#!/usr/bin/env python3
"""Assembles an eleventh reach set (/work/reach-set11) from bare git mirrors of repositories no
earlier set used, with the shared selection of bench/reach/reach_select.py (per source the
sorted mesh files under the listed folders, every k-th over the cap; skipped: files over
30 MB, blobs absent from the snapshot, Git LFS pointers, a blob already taken).
Sources: library test meshes (mikedh/trimesh models/, assimp/assimp test/models,
PyMesh/PyMesh tests/data), research/tutorial models and scans (libigl/libigl-tutorial-data),
printer beds, gantries, shapes and slicer test objects (prusa3d/PrusaSlicer), industrial
robot descriptions (ros-industrial/fanuc, ros-industrial/abb_experimental), simulation
assets (google-research/ravens) and game kits (KenneyNL/Starter-Kit-City-Builder,
KenneyNL/Starter-Kit-3D-Platformer).
Left out by path: copies of files earlier sets took from their own repositories (glTF sample
models in trimesh and assimp, PrusaSlicer's 3DBenchy, ravens' ur5/ meshes: their collision
STLs are blobs an earlier set took). frankaemika/franka_ros was dropped: all 9 of its meshes
are blobs an earlier set took.
Session 59's helper; writes /work/reach-set11/MANIFEST.tsv (copied to
bench/reach/MANIFEST-set11.tsv).
Usage: python3 bench/reach/assemble-set11.py; then PREPARE=auto COMPARE=none JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set11"""
import sys
sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("mikedh/trimesh", "trimesh",
           "MIT (repo LICENSE, Michael Dawson-Haggerty)",
           r"^models/.*" + EXT,
           exclude=r"^models/(Duck|CesiumMilkTruck|BoxTextured|BoxInterleaved|AlphaBlendModeTest)\.glb$", cap=45),
    Source("assimp/assimp", "assimp",
           "BSD-3-Clause (repo LICENSE, assimp team); test/models-nonbsd per file: rifle.obj 'free the models' "
           "(Elias Tsiantas), segment.obj CC-BY-3.0 (TUM kuka_lwr), ant-half.ply its own .license",
           r"^test/models(-nonbsd)?/.*" + EXT,
           exclude=r"(glTF-Sample-Models|2CylinderEngine|AnimatedMorph|BoxTextured-glTF|/glTF/(BoxTextured|CesiumMilkTruck)"
                   r"|ClearCoat|MorphPrimitivesTest|MorphStressTest|SimpleMorph|/cameras/|textureTransform|simple_skin/simple_skin)",
           cap=35),
    Source("prusa3d/PrusaSlicer", "prusaslicer",
           "AGPL-3.0 (repo LICENSE, Prusa Research); printer bed models under resources/profiles/<vendor> are the vendors' "
           "(no separate terms in the tree)",
           r"^(resources|tests)/.*" + EXT, exclude=r"3DBenchy", cap=30),
    Source("ros-industrial/fanuc", "fanuc",
           "BSD-3-Clause (repo LICENSE, TU Delft Robotics Institute)",
           r"^.*" + EXT, cap=20),
    Source("ros-industrial/abb_experimental", "abb_experimental",
           "Apache-2.0 (repo LICENSE)",
           r"^.*" + EXT, cap=15),
    Source("libigl/libigl-tutorial-data", "libigl-tutorial-data",
           "no repo licence; README lists each file's origin (libigl, Stanford scans, AIM@SHAPE, cosmic blobs, "
           "Sorkine 2004, ...; many '?'): unknown",
           r"^.*" + EXT, cap=21),
    Source("google-research/ravens", "ravens",
           "Apache-2.0 (repo LICENSE, Google)",
           r"^ravens/environments/assets/.*" + EXT, exclude=r"/ur5/", cap=12),
    Source("KenneyNL/Starter-Kit-City-Builder", "kenney-city-builder",
           "code MIT (repo LICENSE.md, Kenney); README: 3D models CC0",
           r"^.*" + EXT, cap=8),
    Source("KenneyNL/Starter-Kit-3D-Platformer", "kenney-platformer",
           "code MIT (repo LICENSE.md, Kenney); README: 3D models CC0",
           r"^.*" + EXT, cap=8),
    Source("PyMesh/PyMesh", "pymesh",
           "unknown (no LICENSE file at the top of the snapshot; README without terms)",
           r"^(tests/data|docs/_static)/.*" + EXT, cap=8),
]

OUT = "/work/reach-set11"
rows = assemble(SOURCES, OUT, max_bytes=30e6, dedup=True, ignore_case=True)
with open(f"{OUT}/MANIFEST.tsv", "w") as f:
    f.write("file\tkind\tsource\tpath\tbytes\trepo\tcommit\tlicence\n")
    for r in rows: f.write("\t".join(r) + "\n")
