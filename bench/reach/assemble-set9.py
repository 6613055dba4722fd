#!/usr/bin/env python3
"""Assembles a ninth reach set (/work/reach-set9) from bare git mirrors of repositories no
earlier set used, with the shared selection of bench/reach/reach_select.py (per source the
sorted mesh files under the listed folders, every k-th over the cap; skipped: files over
30 MB, blobs absent from the snapshot, Git LFS pointers, a blob already taken).
Sources: engine/demo assets (KhronosGroup/Vulkan-Samples-Assets, SaschaWillems/Vulkan-Assets,
aframevr/aframe), library test data (mosra/magnum-plugins, ufbx/ufbx incl. a few OBJ fuzz
seeds, facebookresearch/pytorch3d, google-deepmind/mujoco), printer parts
(VoronDesign/Voron-Trident) and classic scan/sample meshes (cnr-isti-vclab/vcglib).
Session 55's helper; writes /work/reach-set9/MANIFEST.tsv (committed as
bench/reach/MANIFEST-set9.tsv).
Usage: python3 bench/reach/assemble-set9.py; then PREPARE=auto COMPARE=none JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set9"""
import sys
sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
from reach_select import Source, assemble

EXT = r"\.(glb|gltf|obj|off|stl|ply|drc)$"
SOURCES = [
    Source("KhronosGroup/Vulkan-Samples-Assets", "vulkan-samples-assets",
           "per model (README): Sponza/vokselia CC-BY-3.0, Bonza/Space Module/primitives/terrain Apache-2.0, "
           "morpheus_team BSD-3-Clause, PICA PICA robot CC-BY-NC-4.0, other scenes by Sascha Willems Apache-2.0; no repo LICENSE file",
           r"^scenes/.*" + EXT),
    Source("SaschaWillems/Vulkan-Assets", "vulkan-assets",
           "no repo licence; README per model: glTF sample models (Khronos), Cerberus by Andrew Maximov, "
           "Retro UFO CC-BY-3.0, Vulkan scene models 'do not use and distribute without request'; others without notes: mixed/unknown",
           r"^models/.*" + EXT, cap=20),
    Source("aframevr/aframe", "aframe",
           "MIT (repo LICENSE); example models without notes of their own",
           r"^(examples|tests)/.*" + EXT),
    Source("mosra/magnum-plugins", "magnum-plugins",
           "MIT (repo COPYING, Vladimír Vondruš and contributors); importer test files",
           r"^src/MagnumPlugins/.*/Test/.*" + EXT, cap=28),
    Source("ufbx/ufbx", "ufbx",
           "MIT or public domain (Unlicense), repo LICENSE; data/ exports without notes of their own",
           r"^data/[^/]*\.obj$", cap=20),
    Source("ufbx/ufbx", "ufbx-fuzz",
           "MIT or public domain (Unlicense), repo LICENSE; OBJ fuzz corpus",
           r"^data/obj_fuzz/.*", cap=8),
    Source("VoronDesign/Voron-Trident", "Voron-Trident",
           "GPL-3.0 (repo LICENSE)",
           r"^STLs/.*" + EXT, cap=22),
    Source("google-deepmind/mujoco", "mujoco",
           "Apache-2.0 (repo LICENSE); test/model meshes without notes of their own (Stanford bunny, spot, Shadow hand, Barkour)",
           r"^(model|test|mjx)/.*" + EXT, cap=23),
    Source("facebookresearch/pytorch3d", "pytorch3d",
           "BSD (repo LICENSE); test/tutorial meshes (cow, teapot, spot) without notes of their own",
           r"^(tests|docs)/.*" + EXT),
    Source("cnr-isti-vclab/vcglib", "vcglib",
           "GPL-3.0 (repo LICENSE.txt); sample meshes without notes of their own",
           r"^apps/.*" + EXT),
]

assemble(SOURCES, "/work/reach-set9", max_bytes=30e6, dedup=True, ignore_case=True)
