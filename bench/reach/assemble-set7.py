#!/usr/bin/env python3
"""Assembles a seventh reach set (/work/reach-set7, session 48) from bare git mirrors of
repositories no earlier set used (reach_select.py: the selection, shared with sets 2-6):
robot and vehicle meshes (kuka_experimental: KUKA arms' STL; PX4-gazebo-models: drones,
rover, gimbal), a visualisation toolkit's example data (pyvista/vtk-data: scans and models,
STL/PLY/OBJ), a printer's printed parts (Original-Prusa-i3: STL exports of OpenSCAD parts),
and game/engine demo assets (BabylonJS/MeshesLibrary: .glb/.gltf scenes, its synthetic
Tests/ left out; godotengine/tps-demo: the .glb files the snapshot holds; KenneyNL
KayKit-Hexagons: .gltf.glb tiles).
Per source, the sorted .glb .gltf .obj .off .stl .ply .drc files under the listed folders,
every k-th over the cap; skipped: files over 30 MB, blobs absent from the snapshot, Git
LFS pointers, a blob already taken. Writes /work/reach-set7/MANIFEST.tsv (committed as
bench/reach/MANIFEST-set7.tsv).
Usage: python3 bench/reach/assemble-set7.py; then PREPARE=auto COMPARE=none JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set7"""
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("ros-industrial/kuka_experimental", "kuka_experimental",
           "Apache-2.0 (repo LICENSE)",
           r"^kuka_[^/]+_support/meshes/.*" + EXT, cap=35),
    Source("PX4/PX4-gazebo-models", "PX4-gazebo-models",
           "BSD-3-Clause (repo LICENSE)",
           r"^models/.*" + EXT),
    Source("pyvista/vtk-data", "vtk-data",
           "Apache-2.0 (repo LICENSE); README asks each dataset's folder to carry its own licence",
           r"^Data/.*" + EXT),
    Source("prusa3d/Original-Prusa-i3", "Original-Prusa-i3",
           "GPL-2.0 (repo LICENSE)",
           r"^Printed-Parts/STL/.*" + EXT, cap=30),
    Source("BabylonJS/MeshesLibrary", "BabylonJS-MeshesLibrary",
           "CC-BY-4.0 unless a folder says otherwise (README 'Licensing')",
           EXT, exclude=r"^Tests/"),
    Source("godotengine/tps-demo", "tps-demo",
           "assets CC-BY-3.0 (Juan Linietsky, Fernando Miguel Calabró), code MIT (LICENSE.md)",
           EXT),
    Source("KenneyNL/KayKit-Hexagons", "KayKit-Hexagons",
           "MIT (repo LICENSE, Kenney)",
           r"^Models/.*" + EXT),
]

assemble(SOURCES, "/work/reach-set7", max_bytes=30e6, dedup=True, ignore_case=True)
