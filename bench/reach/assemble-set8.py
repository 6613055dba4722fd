#!/usr/bin/env python3
"""Assembles an eighth reach set (/work/reach-set8, session 52) from bare git mirrors of
repositories no earlier set used (reach_select.py: the selection, shared with sets 2-7):
game/engine demo assets (bevyengine/bevy: assets/models, glTF/glb; raysan5/raylib: the
models and shaders examples' OBJ/glb; playcanvas/engine: examples' glb, a Draco point
cloud, Gaussian-splat PLYs, test glb/ply, its bitmoji animation clips left out), a printer's
printed parts (VoronDesign/Voron-2: STL), a point-cloud/geometry library's test data
(fwilliams/point-cloud-utils: data/), and a physics suite's models (google-deepmind/
dm_control: the Kinova Jaco arm's full and decimated STL, and the dog model's bone, muscle
and site STL, every k-th).
Per source, the sorted .glb .gltf .obj .off .stl .ply .drc files under the listed folders,
every k-th over the cap; skipped: files over 30 MB, blobs absent from the snapshot, Git
LFS pointers, a blob already taken. Writes /work/reach-set8/MANIFEST.tsv (committed as
bench/reach/MANIFEST-set8.tsv).
Usage: python3 bench/reach/assemble-set8.py; then PREPARE=auto COMPARE=none JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set8"""
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("bevyengine/bevy", "bevy",
           "MIT OR Apache-2.0 (repo LICENSE-MIT, LICENSE-APACHE); CREDITS.md: Kenney kits CC0, "
           "Fox CC0 + CC-BY-4.0 rigging, MorphStressTest CC-BY-4.0; others without notes",
           r"^assets/models/.*" + EXT),
    Source("raysan5/raylib", "raylib",
           "zlib (repo LICENSE); resources/LICENSE.md per model: Alberto Cano's OBJ CC-BY-NC-4.0, "
           "plane.obj CC-BY-4.0, cube.obj/robot.glb/greenman*.glb CC0; others unknown",
           r"^examples/(models|shaders)/resources/.*" + EXT),
    Source("playcanvas/engine", "playcanvas-engine",
           "MIT (repo LICENSE); examples/assets/models: per-model .txt notes (Khronos samples, "
           "Sketchfab CC-BY and others); others without notes",
           r"^(examples/assets/(models|splats|vat)|test/assets)/.*" + EXT),
    Source("VoronDesign/Voron-2", "Voron-2",
           "GPL-3.0 (repo LICENSE)",
           r"^STLs/.*" + EXT, cap=35),
    Source("fwilliams/point-cloud-utils", "point-cloud-utils",
           "MIT (repo LICENSE); data/ without notes of its own",
           r"^data/.*" + EXT),
    Source("google-deepmind/dm_control", "dm_control-kinova",
           "BSD-style (third_party/kinova/LICENSE: Kinova Robotics 2017, dm_control Authors 2018)",
           r"^dm_control/third_party/kinova/.*" + EXT),
    Source("google-deepmind/dm_control", "dm_control-dog",
           "Apache-2.0 (repo LICENSE)",
           r"^dm_control/suite/dog_assets/.*" + EXT, cap=15),
]

assemble(SOURCES, "/work/reach-set8", max_bytes=30e6, dedup=True, ignore_case=True)
