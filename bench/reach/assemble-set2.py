#!/usr/bin/env python3
"""Assembles a second reach set (/work/reach-set2, session 35) from bare git mirrors (the
fetch tool: /work/.mirror/OWNER+NAME/repo): each chosen mesh file plus the files a .gltf names
(buffers, images), and MANIFEST.tsv (file kind source path bytes repo commit licence). Files
over 50 MB, absent from the snapshot, or Git LFS pointers are skipped.
Usage: python3 bench/reach/assemble-set2.py; then COMPARE=none PREPARE=auto JOBS=1
bench/reach/run.sh build/cli/spheremap /work/reach-set2"""
import json, os, re, subprocess, sys
M = "/work/.mirror"
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
def git(repo, *args, text=True):
    return subprocess.run(["git", "--git-dir", f"{M}/{repo.replace('/', '+')}/repo", *args],
                          capture_output=True, text=text, check=True).stdout
rows = []
for repo, (short, lic, inc, exc) in REPOS.items():
    commit = git(repo, "rev-parse", "HEAD").strip()
    sizes = {}
    for line in git(repo, "ls-tree", "-r", "-l", "HEAD").splitlines():
        meta, path = line.split("\t", 1)
        size = meta.split()[3]
        sizes[path] = int(size) if size.isdigit() else None
    def copy(path):
        data = git(repo, "show", f"HEAD:{path}", text=False)
        dst = f"{OUT}/{short}/{path}"
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        open(dst, "wb").write(data)
        return data
    for path in sorted(sizes):
        if not re.search(inc, path) or re.search(exc, path): continue
        size = sizes[path]
        if size is None or size > 50e6: continue  # absent from the snapshot, or too big
        try: data = copy(path)
        except subprocess.CalledProcessError: continue
        if data.startswith(b"version https://git-lfs"): os.remove(f"{OUT}/{short}/{path}"); continue
        if path.endswith(".gltf"):
            try: doc = json.loads(data)
            except ValueError: doc = {}
            for item in (doc.get("buffers") or []) + (doc.get("images") or []):
                uri = item.get("uri", "") if isinstance(item, dict) else ""
                if uri and not uri.startswith("data:"):
                    dep = os.path.normpath(os.path.join(os.path.dirname(path), uri.replace("%20", " ")))
                    if sizes.get(dep): copy(dep)
        first, _, rest = path.partition("/")
        rows.append([f"{short}/{path}", short, first, rest, str(len(data)), repo, commit, lic])
with open(f"{OUT}/MANIFEST.tsv", "w") as f:
    f.write("file\tkind\tsource\tpath\tbytes\trepo\tcommit\tlicence\n")
    for r in rows: f.write("\t".join(r) + "\n")
import collections
print(len(rows), collections.Counter(r[1] for r in rows))
