#include "core/outputs/sphere_glb.h"

#include "core/io/gltf_reader.h"
#include "core/io/scene_glb.h"
#include "core/mesh/sphere_geometry.h"

namespace spheremap {
namespace {

// The sphere's normals: its points, and +z for a vertex of no face, which the input's layout
// keeps at the origin (glTF normals must be unit vectors: gpytoolbox's bunny.ply, with 1,113
// unused vertices, was written with 1,113 validator errors).
std::vector<Vec3> sphere_normals(const std::vector<Vec3>& positions) {
  std::vector<Vec3> normals = positions;
  for (Vec3& n : normals)
    if (n.x == 0 && n.y == 0 && n.z == 0) n = Vec3{0, 0, 1};
  return normals;
}

}  // namespace

WrittenGlb sphere_glb(const PolygonMesh& sphere, bool inward, int draco_position_bits,
                      const SphereLook& look, bool without_fills,
                      std::span<const std::array<float, 3>> colors) {
  WrittenGlb out;
  const std::vector<Triangle> triangles = fan_triangulate(sphere).triangles;
  if (look.appearance) {
    SceneGeometry geometry;
    geometry.input = look.input;
    geometry.positions = sphere.positions;
    geometry.normals = sphere_normals(sphere.positions);
    geometry.skip_face = look.skip_face;
    out.glb = build_scene_glb(*look.appearance, geometry, nlohmann::json::object());
  } else {
    GlbMesh mesh;
    mesh.positions = sphere.positions;
    mesh.normals = sphere_normals(sphere.positions);
    mesh.triangles = triangles;
    mesh.draco_position_bits = draco_position_bits;
    if (colors.size() == sphere.positions.size()) mesh.colors.assign(colors.begin(), colors.end());
    out.glb = build_glb(mesh);
  }
  const std::string bytes = serialize_glb(out.glb);
  const PolygonMesh decoded =
      read_gltf({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()});
  std::vector<Triangle> oriented = fan_triangulate(decoded).triangles;
  if (inward)
    for (Triangle& t : oriented) std::swap(t[1], t[2]);
  // Quantized points sit slightly off the sphere; a reader takes their directions (the
  // signs of the determinants do not change). Unused vertices belong to no face.
  std::vector<Vec3> directions(decoded.positions.size());
  for (size_t v = 0; v < directions.size(); ++v)
    directions[v] = normalized_or(decoded.positions[v], Vec3{});
  out.check = check_map(directions, oriented);
  if (without_fills) out.check.bijective = out.check.folds == 0;
  // Every face written (the scene's vertices may come in another number: a primitive
  // whose faces were all dropped is not written).
  if (oriented.size() != triangles.size()) out.check.bijective = false;
  return out;
}

}  // namespace spheremap
