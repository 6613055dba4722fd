#!/usr/bin/env python3
"""Assembles a second reach set (/work/reach-set2, session 35) from bare git mirrors (the
fetch tool: /work/.mirror/OWNER+NAME/repo): each chosen mesh file plus the files a .gltf names
(buffers, images), and MANIFEST.tsv (file kind source path bytes repo commit licence). Files
over 50 MB, absent from the snapshot, or Git LFS pointers are skipped.
Usage: python3 bench/reach/assemble-set2.py; then COMPARE=none PREPARE=auto JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set2
The selection itself is reach_select.py (shared with the other set scripts)."""
OUT = "/work/reach-set2"
REPOS = {  # repo -> (short name, licence as stated, include regex, exclude regex)
 "google/draco": ("draco", "Apache-2.0 (repo LICENSE; testdata/KhronosSampleModels: Khronos sample-model licences)",
   r"^testdata/.*\.(gltf|glb|obj|ply|stl)$|^testdata/(car|bunny_gltf)\.drc$",
   r"UnusedTexCoords/(?!MultiUVTest)|UnlitWithFallback/(?!one_material)|_(312|321)\.obj$|test_nm_trans|"
   r"three_materials|Triangle_identity|Triangle_translation|one_face_123_(mirror|translated)|sphere_no_tangents|"
   r"sphere_two_tex|sphere_lights|cube_att_sub_o_2|TextureTransformTestWithRequired|KhrTextureTransformWithFallback|"
   r"BoxMeta/|test_sphere\.obj|mat_test|delim_test|SpecGlossVsMetalRough|TextureSettingsTest"),
 "pmp-library/pmp-library": ("pmp", "MIT (repo LICENSE.txt; data/README.md credits Stanford, Hoppe, Bommes, Sutherland, Botsch, Blender)",
   r"^data/.*\.(obj|off|stl)$", r"^$"),
 "KhronosGroup/glTF-Blender-IO": ("blender-io", "Apache-2.0 (repo LICENSE.txt)",
   r"^tests/roundtrip/.*\.gltf$|^tests/gltf/Box\.glb$",
   r"0[148]_(alpha|principled|unlit|common_mat|lenna|sphere_spec|combine)|1[1-9]_|2[05]_|22_factors|20_spec|"
   r"01_textured_sphere_principled|05_metallic_sphere_light|roundtrip/Box/"),
 "elalish/manifold": ("manifold", "Apache-2.0 (repo LICENSE; extras/ember_tests STLs: Thingi10K, per-model Thingiverse licences)",
   r"^(bindings/wasm/test/(fixtures|examples)/models/.*\.(glb|obj)|samples/models/.*\.glb|test/models/.*\.obj|extras/ember_tests/testfiles/raw_meshes/.*\.stl)$",
   r"fixtures/models/space\.glb"),
 "zeux/meshoptimizer": ("meshoptimizer", "MIT (repo LICENSE.md)", r"^(demo/pirate\.(glb|obj)|gltf/fuzz\.glb)$", r"^$"),
}
from reach_select import Source, assemble
assemble([Source(repo, short, lic, inc, None if exc == r"^$" else exc) for repo, (short, lic, inc, exc) in REPOS.items()],
         OUT, max_bytes=50e6)
