"""Fan-triangulates an OBJ's polygons (v and f lines only, vertex order kept), for tools
that take triangles only (Praun & Hoppe's SphereParam stops on beast's quads). Each fan's
apex is the first corner whose diagonals are neither an edge of the mesh nor a diagonal
already used: a plain fan from corner 0 makes 2 non-manifold edges on beast.
Usage: triangulate_obj.py IN.obj OUT.obj"""
import sys

vertices, faces = [], []
with open(sys.argv[1]) as src:
    for line in src:
        if line.startswith("v "):
            vertices.append(line)
        elif line.startswith("f "):
            faces.append([c.split("/")[0] for c in line.split()[1:]])
edges = {frozenset((f[k], f[(k + 1) % len(f)])) for f in faces for k in range(len(f))}
used = set()
with open(sys.argv[2], "w") as dst:
    dst.writelines(vertices)
    for f in faces:
        n = len(f)
        apex = 0
        for k in range(n):
            diagonals = {frozenset((f[k], f[(k + j) % n])) for j in range(2, n - 1)}
            if not (diagonals & edges) and not (diagonals & used):
                apex = k
                break
        f = f[apex:] + f[:apex]
        used |= {frozenset((f[0], f[j])) for j in range(2, n - 1)}
        for k in range(1, n - 1):
            dst.write(f"f {f[0]} {f[k]} {f[k + 1]}\n")
