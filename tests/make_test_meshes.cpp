// Writes the generated test meshes as GLB files for the shell tests and the load bench
// (no corpus needed): make_test_meshes OUTDIR -> OUTDIR/{icosphere2,icosphere4,horseshoe,
// torus}.glb
#include <cstdio>
#include <string>

#include "core/io/glb_writer.h"
#include "core/io/mesh_file.h"
#include "tests/mesh_generators.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_test_meshes OUTDIR\n");
    return 1;
  }
  using namespace spheremap;
  const std::string dir = argv[1];
  auto write = [&](const std::string& name, const PolygonMesh& mesh) {
    GlbMesh glb;
    glb.positions = mesh.positions;
    glb.triangles = fan_triangulate(mesh).triangles;
    write_binary_file(dir + "/" + name + ".glb", format_glb(glb));
  };
  write("icosphere2", testing::icosphere(2));  // 320 triangles
  write("icosphere4", testing::icosphere(4));  // 5,120 triangles
  write("horseshoe", testing::horseshoe());    // 744 triangles, the paper's loop never unfolds it
  write("torus", testing::torus(16, 12));      // genus 1: refused with 422
  return 0;
}
