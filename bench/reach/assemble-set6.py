#!/usr/bin/env python3
"""Assembles a sixth reach set (/work/reach-set6, session 40) from bare git mirrors of
repositories no earlier set used (reach_select.py: the selection, shared with sets 2-5):
robot description meshes (moveit_resources: PR2, Panda, Fanuc; icub-models: iCub's
SimMechanics STL exports; universal_robot: UR arms' collision meshes), a graphics example-mesh collection (odedstein/meshes: OBJ scans
and models), a repair tool's inputs (ManifoldPlus: OBJ/OFF with defects) and three.js demo
scenes packed by gltfpack (3d-demo-data: .glb/.gltf with meshopt compression).
Per source, the sorted .glb .gltf .obj .off .stl .ply .drc files under the listed folders,
every k-th over the cap; skipped: files over 30 MB, blobs absent from the snapshot, Git
LFS pointers, a blob already taken. Writes /work/reach-set6/MANIFEST.tsv (committed as
bench/reach/MANIFEST-set6.tsv).
Usage: python3 bench/reach/assemble-set6.py; then PREPARE=auto COMPARE=none JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set6"""
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("moveit/moveit_resources", "moveit_resources",
           "per package: pr2_description BSD (package.xml), panda_description Apache-2.0 (its LICENSE), "
           "fanuc_description BSD (its LICENSE, TU Delft)",
           r"^[^/]+_description/.*" + EXT, cap=35),
    Source("robotology/icub-models", "icub-models",
           "CC-BY-SA-4.0 (repo LICENSE)",
           r"^iCub[^/]*/meshes.*" + EXT, cap=30),
    Source("odedstein/meshes", "odedstein-meshes",
           "per object (objects/*/README.md: attribution, original licence; CC-BY, CC-BY-NC, public domain ...)",
           r"^objects/.*" + EXT, cap=35),
    Source("hjwdzh/ManifoldPlus", "ManifoldPlus",
           "no licence file; README 'Copyright' section: BSD-style notice (redistribution with the notice)",
           r"^data/.*" + EXT),
    Source("ros-industrial/universal_robot", "universal_robot",
           "BSD (ur_description/package.xml); ur20 and ur30 meshes: Universal Robots A/S' terms "
           "(meshes/ur20/LICENSE.txt, meshes/ur30/LICENSE.txt)",
           r"^ur_description/meshes/.*" + EXT, cap=14),
    Source("gkjohnson/3d-demo-data", "3d-demo-data",
           "per model (README: 'not intended for general distribution', source link and terms in each folder)",
           r"^models/.*" + EXT, cap=50),
]

assemble(SOURCES, "/work/reach-set6", max_bytes=30e6, dedup=True, ignore_case=True)
