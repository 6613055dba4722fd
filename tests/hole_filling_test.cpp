// Closing small holes (core/prepare/hole_filling.h): fills over the hole's own corners that
// close the surface without a non-manifold edge, run the way the hole's faces do, stop at
// the size bound, and let the mesh map certified with the fills left out of its sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <vector>

#include "core/map/certification.h"
#include "core/map/metrics.h"
#include "core/map/pipeline.h"
#include "core/mesh/sphere_geometry.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "core/outputs/report_json.h"
#include "core/outputs/sphere_asset.h"
#include "core/prepare/fill_refinement.h"
#include "core/prepare/hole_filling.h"
#include "core/prepare/prepare_mesh.h"
#include "tests/mesh_generators.h"

namespace spheremap {
namespace {

// `mesh` without every face that uses vertex `v` (a hole as large as its ring).
PolygonMesh without_ring(const PolygonMesh& mesh, uint32_t v) {
  PolygonMesh out;
  out.positions = mesh.positions;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    if (std::find(face.begin(), face.end(), v) == face.end()) out.add_face(face);
  }
  return weld(out, 0).mesh;  // the ring's centre, now unused, dropped
}

void expect_closed_genus0(const PolygonMesh& mesh) {
  const TopologyReport topology = analyze_topology(mesh);
  EXPECT_TRUE(mapping_failures(topology).empty()) << mapping_failures(topology).front().message;
}

TEST(HoleFilling, ClosesHolesOfOneFaceAndOfAWholeRing) {
  PolygonMesh one = testing::without_face(testing::icosphere(2), 7);
  const HoleFilling a = fill_holes(one, 0.05);
  EXPECT_EQ(a.holes_filled, 1u);
  EXPECT_EQ(a.faces_added, 1u);
  expect_closed_genus0(one);

  // Quads around a vertex of valence 4 and triangles around one of valence 6.
  for (PolygonMesh mesh :
       {without_ring(testing::quad_sphere(6), 30), without_ring(testing::icosphere(3), 200)}) {
    const size_t corners = analyze_topology(mesh).boundary_edges;
    const HoleFilling filled = fill_holes(mesh, 0.05);
    EXPECT_EQ(filled.holes_filled, 1u);
    // A polygon of n corners: n - 2 triangles, and 2 more per vertex the refinement adds.
    EXPECT_EQ(filled.faces_added, corners - 2 + 2 * filled.vertices_added);
    EXPECT_GT(filled.largest_fill, 0);
    expect_closed_genus0(mesh);
  }
}

TEST(HoleFilling, LeavesHolesLargerThanTheBound) {
  // Half a sphere: its fill (the disc) is about half its area.
  const PolygonMesh sphere = testing::icosphere(3);
  PolygonMesh half;
  half.positions = sphere.positions;
  for (size_t f = 0; f < sphere.face_count(); ++f) {
    const auto face = sphere.face(f);
    if (sphere.positions[face[0]].z > 0 && sphere.positions[face[1]].z > 0 &&
        sphere.positions[face[2]].z > 0)
      half.add_face(face);
  }
  half = weld(half, 0).mesh;
  const size_t faces = half.face_count();
  PolygonMesh copy = half;
  const HoleFilling bounded = fill_holes(copy, 0.05);
  EXPECT_EQ(bounded.holes_filled, 0u);
  EXPECT_EQ(bounded.holes_left, 1u);
  EXPECT_EQ(copy.face_count(), faces);
  const HoleFilling none = fill_holes(copy, 0);
  EXPECT_EQ(none.holes_filled + none.holes_left, 0u);
  // Allowed up to its whole area, it is closed (a dome on a flat base).
  const HoleFilling large = fill_holes(copy, 1.0);
  EXPECT_EQ(large.holes_filled, 1u);
  EXPECT_GT(large.largest_fill, 0.3);
  expect_closed_genus0(copy);
}

TEST(HoleFilling, NeverReusesAnEdgeTheMeshHas) {
  // A tetrahedron without one face: the hole's three corners are joined by the mesh's own
  // edges, and its fill is that face, whose edges are the hole's: allowed.
  PolygonMesh tetra = testing::without_face(testing::two_tetrahedra(), 0);
  tetra = weld(tetra, 0).mesh;
  fill_holes(tetra, 1.0);
  EXPECT_TRUE(analyze_topology(tetra).manifold());
  // A square pyramid with its base open, the base bent so that the least-area fill takes
  // the diagonal 0-2; with a closed flap over 0-2 (both faces), that edge exists and the
  // fill must take 1-3.
  auto pyramid = [](bool flap) {
    PolygonMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 1}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 2}, {0.5, 0.5, -1}};
    for (std::vector<uint32_t> f :
         {std::vector<uint32_t>{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}})
      m.add_face(f);
    if (flap) {
      m.add_face(std::vector<uint32_t>{0, 2, 5});
      m.add_face(std::vector<uint32_t>{2, 0, 5});
    }
    return m;
  };
  auto has_edge = [](const PolygonMesh& m, size_t from_face, uint32_t a, uint32_t b) {
    for (size_t f = from_face; f < m.face_count(); ++f) {
      const auto face = m.face(f);
      const bool with_a = std::find(face.begin(), face.end(), a) != face.end();
      const bool with_b = std::find(face.begin(), face.end(), b) != face.end();
      if (with_a && with_b) return true;
    }
    return false;
  };
  PolygonMesh plain = pyramid(false);
  ASSERT_EQ(fill_holes(plain, 1.0).faces_added, 2u);
  EXPECT_TRUE(has_edge(plain, 4, 0, 2));
  PolygonMesh flapped = pyramid(true);
  ASSERT_EQ(fill_holes(flapped, 1.0).faces_added, 2u);
  EXPECT_TRUE(has_edge(flapped, 6, 1, 3));
  EXPECT_FALSE(has_edge(flapped, 6, 0, 2));
  EXPECT_EQ(analyze_topology(flapped).non_manifold_edges, 0u);
}

TEST(HoleFilling, AMeshWithHolesMapsCertifiedAndSaysWhatWasClosed) {
  PolygonMesh input = without_ring(testing::horseshoe(), 40);
  input = testing::without_face(input, 100);
  const PreparedMesh prepared = prepare_input(input, nullptr, {});
  EXPECT_EQ(prepared.preparation.holes_filled, 2u);
  ASSERT_TRUE(input_failures(prepared).empty());
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
  // The sphere in the input's layout has the holes (the fills are not input faces); its
  // file is checked for folds and degenerate triangles.
  const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
  EXPECT_TRUE(sphere.metrics["bijective"]);
  EXPECT_EQ(sphere.written.triangles + prepared.preparation.faces_added,
            mapped.map.check.triangles);
  EXPECT_EQ(sphere.metrics["preparation"]["holes_filled"], 2);

  // exact refuses the holes; a bound of 0 leaves them.
  PolygonMesh again = input;
  PrepareOptions exact;
  exact.method = PrepareMethod::kExact;
  EXPECT_EQ(input_failures(prepare_input(again, nullptr, exact)).front().check, "boundary");
  PrepareOptions none;
  none.max_hole_fill = 0;
  EXPECT_EQ(input_failures(prepare_input(again, nullptr, none)).front().check, "boundary");
}

// A unit icosphere without its faces above z = `height`, welded: one round hole.
PolygonMesh sphere_without_cap(int levels, double height) {
  const PolygonMesh sphere = testing::icosphere(levels);
  PolygonMesh out;
  out.positions = sphere.positions;
  for (size_t f = 0; f < sphere.face_count(); ++f) {
    const auto face = sphere.face(f);
    if (!std::all_of(face.begin(), face.end(),
                     [&](uint32_t v) { return sphere.positions[v].z > height; }))
      out.add_face(face);
  }
  return weld(out, 0).mesh;
}

// A tube of unit radius and length 3 open at both ends (two holes of 32 corners).
PolygonMesh open_tube() {
  const PolygonMesh capped = testing::capped_tube(32, 24, 3);
  PolygonMesh out;
  out.positions = capped.positions;
  for (size_t f = 0; f + 2 < capped.face_count(); ++f) out.add_face(capped.face(f));
  return out;
}

// The mean length of the edges with a face on one side only.
double mean_boundary_edge(const PolygonMesh& mesh) {
  std::set<std::pair<uint32_t, uint32_t>> half_edges;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k)
      half_edges.insert({face[k], face[(k + 1) % face.size()]});
  }
  double sum = 0;
  size_t count = 0;
  for (const auto& [a, b] : half_edges)
    if (!half_edges.count({b, a})) sum += norm(mesh.positions[a] - mesh.positions[b]), ++count;
  return count ? sum / static_cast<double>(count) : 0;
}

// The longest edge of the faces from `first` on.
double longest_edge(const PolygonMesh& mesh, size_t first) {
  double longest = 0;
  for (size_t f = first; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    for (size_t k = 0; k < face.size(); ++k)
      longest = std::max(
          longest, norm(mesh.positions[face[k]] - mesh.positions[face[(k + 1) % face.size()]]));
  }
  return longest;
}

TEST(HoleFilling, RefinedFillsHaveEdgesLikeTheBoundarys) {
  struct Case {
    PolygonMesh mesh;
    size_t holes;
  };
  for (Case c :
       {Case{sphere_without_cap(4, 0.6), 1}, Case{open_tube(), 2}, Case{testing::dome(4), 1}}) {
    const PolygonMesh before = c.mesh;
    const double boundary = mean_boundary_edge(c.mesh);
    const size_t corners = analyze_topology(c.mesh).boundary_edges;
    PolygonMesh flat = c.mesh;
    fill_holes(flat, 1.0, nullptr, false);
    const HoleFilling filled = fill_holes(c.mesh, 1.0);
    ASSERT_EQ(filled.holes_filled, c.holes);
    EXPECT_GT(filled.vertices_added, 0u);
    EXPECT_EQ(filled.holes_faired, c.holes);
    EXPECT_LE(filled.vertices_added, corners * corners / 4);
    EXPECT_EQ(c.mesh.vertex_count(), before.vertex_count() + filled.vertices_added);
    EXPECT_EQ(filled.faces_added, corners - 2 * c.holes + 2 * filled.vertices_added);
    // No vertex of the mesh moved, and its faces are as they were.
    EXPECT_TRUE(
        std::equal(before.positions.begin(), before.positions.end(), c.mesh.positions.begin()));
    EXPECT_TRUE(std::equal(before.indices.begin(), before.indices.end(), c.mesh.indices.begin()));
    // The flat fill spans the hole with edges many boundary edges long; the refined one
    // has edges about the boundary's.
    const double refined = longest_edge(c.mesh, before.face_count()) / boundary;
    const double least_area = longest_edge(flat, before.face_count()) / boundary;
    EXPECT_LT(refined, 3.0) << "least-area fill: " << least_area;
    EXPECT_GT(least_area, 4.0);
    expect_closed_genus0(c.mesh);
  }
}

TEST(HoleFilling, FairedCapsContinueTheSurface) {
  // A sphere without its cap above z = 0.6: the flat fill lies up to 0.4 inside the
  // sphere; the faired cap's new vertices lie close to it (measured: at most 0.067 off; the
  // discrete thin plate over the ring is not exactly the sphere).
  PolygonMesh mesh = sphere_without_cap(4, 0.6);
  const size_t vertices = mesh.vertex_count();
  const HoleFilling filled = fill_holes(mesh, 1.0);
  ASSERT_EQ(filled.holes_faired, 1u);
  double off = 0;
  for (size_t v = vertices; v < mesh.vertex_count(); ++v)
    off = std::max(off, std::abs(norm(mesh.positions[v]) - 1));
  EXPECT_LT(off, 0.1);
  // The least-area fill: its triangles' centroids lie far inside the sphere.
  PolygonMesh flat = sphere_without_cap(4, 0.6);
  const size_t faces = flat.face_count();
  fill_holes(flat, 1.0, nullptr, false);
  double flat_off = 0;
  for (size_t f = faces; f < flat.face_count(); ++f) {
    const auto t = flat.face(f);
    const Vec3 centroid =
        (flat.positions[t[0]] + flat.positions[t[1]] + flat.positions[t[2]]) * (1.0 / 3);
    flat_off = std::max(flat_off, std::abs(norm(centroid) - 1));
  }
  EXPECT_GT(flat_off, 0.2);
  EXPECT_LT(off, flat_off / 4);
}

TEST(HoleFilling, RefinedFillsMapCertified) {
  for (const PolygonMesh& shape : {sphere_without_cap(4, 0.6), open_tube(), testing::dome(4)}) {
    PolygonMesh input = shape;
    PrepareOptions options;
    options.max_hole_fill = 1.0;
    const PreparedMesh prepared = prepare_input(input, nullptr, options);
    ASSERT_TRUE(input_failures(prepared).empty());
    EXPECT_GT(prepared.preparation.vertices_added, 0u);
    EXPECT_EQ(prepared.welded.mesh.vertex_count(),
              shape.vertex_count() + prepared.preparation.vertices_added);
    const MappedMesh mapped = map_prepared(prepared, {});
    EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
    const SphereAsset sphere = sphere_asset(input, mapped, {}, SphereLayout::kOriginal, 0);
    EXPECT_TRUE(sphere.metrics["bijective"]);
    EXPECT_EQ(sphere.metrics["preparation"]["vertices_added"], prepared.preparation.vertices_added);
  }
}

TEST(HoleFilling, TheFillsAreListedForTheMapThroughThePartsStep) {
  // Two parts, each with a hole: the parts step renames the welded vertices, and the list
  // of filled triangles the map weighs down follows, one per face added.
  PolygonMesh input = testing::assembled(
      {{sphere_without_cap(3, 0.6), Vec3{0, 0, 0}}, {open_tube(), Vec3{5, 0, 0}}});
  PrepareOptions options;
  options.max_hole_fill = 1.0;
  const PreparedMesh prepared = prepare_input(input, nullptr, options);
  ASSERT_TRUE(input_failures(prepared).empty());
  ASSERT_EQ(prepared.preparation.holes_filled, 3u);
  ASSERT_EQ(prepared.filled.size(), prepared.preparation.faces_added);
  std::set<std::array<uint32_t, 3>> faces;
  auto key = [](std::array<uint32_t, 3> t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  for (size_t f = 0; f < prepared.welded.mesh.face_count(); ++f)
    if (prepared.welded.mesh.face_size(f) == 3) {
      const auto face = prepared.welded.mesh.face(f);
      faces.insert(key({face[0], face[1], face[2]}));
    }
  for (const Triangle& t : prepared.filled) EXPECT_TRUE(faces.count(key(t)));
  EXPECT_EQ(prepared.welded.mesh.face_count(), input.face_count() + prepared.filled.size());
  const MappedMesh mapped = map_prepared(prepared, {});
  EXPECT_TRUE(certify(mapped, mapped.float32_check).certified);
}

// A sphere without its cap above z = 0.6, prepared with the cap filled (refined, faired),
// and how many faces were its own (the prepared mesh's first ones).
struct CapFilledSphere {
  PreparedMesh prepared;
  size_t own_faces = 0;
};
CapFilledSphere cap_filled_sphere() {
  PolygonMesh input = sphere_without_cap(4, 0.6);
  CapFilledSphere out;
  out.own_faces = input.face_count();
  PrepareOptions prepare;
  prepare.max_hole_fill = 1.0;
  out.prepared = prepare_input(input, nullptr, prepare);
  return out;
}

TEST(HoleFilling, WeighingTheFillDownGivesTheInputsFacesTheirRoom) {
  // A sphere without its cap above z = 0.6, the cap filled (refined, faired): with the
  // fill weighed 0.1 in the energy, the input's own faces take more of the sphere, their
  // area distortion (mean |log| of the area ratio) well below that with the fill weighed
  // like them (the lat-long sphere of bench/fill_bench: 0.23 -> 0.09).
  const CapFilledSphere sphere = cap_filled_sphere();
  const PreparedMesh& prepared = sphere.prepared;
  const size_t own_faces = sphere.own_faces;
  ASSERT_TRUE(input_failures(prepared).empty());
  const PolygonMesh& mesh = prepared.welded.mesh;
  const OrientedTriangles oriented = oriented_triangles(mesh);
  const std::span<const Triangle> own(oriented.triangles.data(), own_faces);
  double distortion[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    MapOptions options;
    options.filled_weight = k == 0 ? 1.0 : 0.1;
    const MappedMesh mapped = map_prepared(prepared, options);
    ASSERT_TRUE(certify(mapped, mapped.float32_check).certified);
    distortion[k] = compute_metrics(mesh.positions, mapped.map.sphere, own).area_log_ratio.mean;
  }
  EXPECT_LT(distortion[1], 0.7 * distortion[0]);
}

// The map's quality metrics are the input's: the fill, weighed down and squeezed on
// purpose, is left out of them, and each own face's share of the sphere is taken of the
// part the own faces cover.
TEST(HoleFilling, TheQualityMetricsMeasureTheInputsOwnFaces) {
  const CapFilledSphere sphere = cap_filled_sphere();
  const PreparedMesh& prepared = sphere.prepared;
  const size_t own_faces = sphere.own_faces;
  ASSERT_TRUE(input_failures(prepared).empty());
  ASSERT_GT(prepared.welded.mesh.face_count(), own_faces);
  const MappedMesh mapped = map_prepared(prepared, {});
  ASSERT_TRUE(certify(mapped, mapped.float32_check).certified);
  EXPECT_EQ(mapped.quality.measured_triangles + mapped.quality.skipped_triangles, own_faces);
  // The area distortion: each own face's share of the sphere the own faces cover over its
  // share of their surface (the fill's room not counted against them).
  const PolygonMesh& mesh = prepared.welded.mesh;
  const OrientedTriangles oriented = oriented_triangles(mesh);
  const std::span<const Triangle> own(oriented.triangles.data(), own_faces);
  double covered = 0;
  for (const Triangle& t : own)
    covered +=
        spherical_area(mapped.map.sphere[t[0]], mapped.map.sphere[t[1]], mapped.map.sphere[t[2]]);
  const QualityMetrics expected =
      compute_metrics(mesh.positions, mapped.map.sphere, own, 1, covered);
  EXPECT_NEAR(mapped.quality.area_log_ratio.mean, expected.area_log_ratio.mean, 1e-9);
}

}  // namespace
}  // namespace spheremap
