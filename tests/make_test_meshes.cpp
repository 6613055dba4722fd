// Writes the generated test meshes as GLB files for the shell tests and the load bench
// (no corpus needed): make_test_meshes OUTDIR -> OUTDIR/{icosphere2,icosphere4,horseshoe,
// torus,textured_horseshoe,ellipsoid}.glb; with --stress [--million], the stress set as OBJ
// (bench/quality); with --stress-glb, the stress set as GLB (the service's slow jobs in tests and
// benches); with --random COUNT SEED, random_stress_meshes as OBJ (the stress probe); with
// --scatter COUNT SEED, quad_scatter as OUTDIR/scatter_COUNT_SEED.obj; with --instanced COUNT,
// an open sphere drawn COUNT times by GPU instancing as OUTDIR/instanced_COUNT.glb. OUTDIR is
// made when missing.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "core/io/glb_writer.h"
#include "core/io/mesh_file.h"
#include "tests/mesh_generators.h"
#include "tests/thin_plates.h"

namespace {

int write_meshes(int argc, char** argv) {
  using namespace spheremap;
  const std::string flag = argc >= 3 ? argv[2] : "";
  // An OUTDIR that looks like an option (--help, -h) is a request for the usage, not a folder.
  const bool asks_usage = argc >= 2 && argv[1][0] == '-';
  if (argc >= 2 && !asks_usage) std::filesystem::create_directories(argv[1]);
  if (flag == "--random" && argc == 5) {
    const std::string dir = argv[1];
    for (const testing::NamedMesh& m : testing::random_stress_meshes(
             std::stoi(argv[3]), static_cast<unsigned>(std::stoul(argv[4]))))
      write_mesh_file(dir + "/" + m.name + ".obj", m.mesh);
    return 0;
  }
  if (flag == "--scatter" && argc == 5) {
    write_mesh_file(
        std::string(argv[1]) + "/scatter_" + argv[3] + "_" + argv[4] + ".obj",
        testing::quad_scatter(std::stoi(argv[3]), static_cast<unsigned>(std::stoul(argv[4]))));
    return 0;
  }
  if (flag == "--instanced" && argc == 4) {
    // An open sphere (its first 8 faces taken out: a hole) drawn COUNT times with
    // EXT_mesh_gpu_instancing: each copy a part the preparation works on.
    const PolygonMesh sphere = testing::icosphere(4);
    PolygonMesh open;
    open.positions = sphere.positions;
    for (size_t f = 8; f < sphere.face_count(); ++f) open.add_face(sphere.face(f));
    write_binary_file(std::string(argv[1]) + "/instanced_" + argv[3] + ".glb",
                      testing::instanced_glb(open, std::stoul(argv[3])));
    return 0;
  }
  if (flag == "--plates" && argc == 3) {
    for (const testing::NamedMesh& m : testing::thin_plates())
      write_mesh_file(std::string(argv[1]) + "/" + m.name + ".obj", m.mesh);
    return 0;
  }
  if (asks_usage || argc < 2 || argc > 4 ||
      (argc >= 3 && flag != "--stress" && flag != "--stress-glb")) {
    std::fprintf(asks_usage ? stdout : stderr,
                 "usage: make_test_meshes OUTDIR [--stress [--million] | --stress-glb | --plates | "
                 "--random COUNT SEED | --scatter COUNT SEED | --instanced COUNT]\n");
    return asks_usage ? 0 : 1;
  }
  const std::string dir = argv[1];
  if (flag == "--stress") {
    const bool million = argc == 4 && std::string(argv[3]) == "--million";
    for (const testing::NamedMesh& m : testing::stress_meshes(million))
      write_mesh_file(dir + "/" + m.name + ".obj", m.mesh);
    return 0;
  }
  auto write = [&](const std::string& name, const PolygonMesh& mesh) {
    GlbMesh glb;
    glb.positions = mesh.positions;
    glb.triangles = fan_triangulate(mesh).triangles;
    write_binary_file(dir + "/" + name + ".glb", format_glb(glb));
  };
  if (flag == "--stress-glb") {
    for (const testing::NamedMesh& m : testing::stress_meshes(false)) write(m.name, m.mesh);
    return 0;
  }
  write("icosphere2", testing::icosphere(2));  // 320 triangles
  write("icosphere4", testing::icosphere(4));  // 5,120 triangles
  write("horseshoe", testing::horseshoe());    // 744 triangles, the paper's loop never unfolds it
  write("torus",
        testing::torus(16, 12));  // genus 1: 422 under prepare=parts with max_handle_cycle=0
  // Elongated, 1 x 1 x 5 along z (depth from the front): the page must frame it side-on.
  write("ellipsoid", testing::scaled(testing::icosphere(3), {1.0, 1.0, 5.0}));
  // Seams on every edge, TEXCOORD_0 and an embedded texture: outputs must keep them.
  write_binary_file(dir + "/textured_horseshoe.glb", testing::textured_glb(testing::horseshoe()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return write_meshes(argc, argv);
  } catch (const std::exception& e) {  // a folder that cannot be made or written, a bad count
    std::fprintf(stderr, "make_test_meshes: %s\n", e.what());
    return 1;
  }
}
