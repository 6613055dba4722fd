#include "core/io/stl.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "core/io/byte_order.h"
#include "core/io/text_reader.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

constexpr size_t kHeaderBytes = 84;  // 80 free bytes, then the uint32 triangle count
constexpr size_t kFacetBytes = 50;   // normal, 3 corners (float32 x 3 each), uint16 attribute

uint32_t declared_triangles(std::string_view bytes) {
  return load_little_endian<uint32_t>(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
}

uint64_t binary_size_for(uint32_t triangles) {
  return kHeaderBytes + kFacetBytes * static_cast<uint64_t>(triangles);
}

bool begins_with_solid(std::string_view bytes) {
  const size_t start = bytes.find_first_not_of(" \t\r\n");
  return start != std::string_view::npos && bytes.substr(start, 5) == "solid";
}

[[noreturn]] void fail(const std::string& message) {
  throw InputError("parse", "STL: " + message);
}

// One pass over the corners: a NaN or infinite coordinate would poison the weld and every
// area after it, so the file is refused with how many there are.
void reject_non_finite(const PolygonMesh& mesh) {
  size_t bad = 0, first = 0;
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3& p = mesh.positions[v];
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
    if (bad++ == 0) first = v;
  }
  if (bad > 0)
    fail(std::to_string(bad) + " of " + std::to_string(mesh.positions.size()) +
         " corners have a non-finite coordinate (NaN or infinity), the first in triangle " +
         std::to_string(first / 3));
}

// Triangle t is corners 3t, 3t+1, 3t+2: the index arrays are filled in one go.
void make_triangle_soup(PolygonMesh& mesh, size_t triangles) {
  mesh.indices.resize(3 * triangles);
  mesh.offsets.resize(triangles + 1);
  for (size_t i = 0; i < mesh.indices.size(); ++i) mesh.indices[i] = static_cast<uint32_t>(i);
  for (size_t t = 0; t <= triangles; ++t) mesh.offsets[t] = static_cast<uint32_t>(3 * t);
}

void check_triangle_cap(size_t triangles, const MeshLimits& limits) {
  if (triangles > limits.max_triangles)
    throw InputError("too_large", "STL: " + std::to_string(triangles) +
                                      " triangles, over the limit of " +
                                      std::to_string(limits.max_triangles));
}

PolygonMesh parse_binary(std::string_view bytes, const MeshLimits& limits) {
  const size_t triangles = declared_triangles(bytes);
  check_triangle_cap(triangles, limits);
  if (3 * static_cast<uint64_t>(triangles) > std::numeric_limits<uint32_t>::max())
    fail(std::to_string(triangles) + " triangles are more than 32-bit indices can hold");
  PolygonMesh mesh;
  mesh.positions.resize(3 * triangles);
  const auto* facet = reinterpret_cast<const unsigned char*>(bytes.data()) + kHeaderBytes;
  for (size_t t = 0; t < triangles; ++t, facet += kFacetBytes) {
    const unsigned char* corner = facet + 12;  // after the normal
    for (size_t k = 0; k < 3; ++k, corner += 12)
      mesh.positions[3 * t + k] = {load_little_endian<float>(corner),
                                   load_little_endian<float>(corner + 4),
                                   load_little_endian<float>(corner + 8)};
  }
  make_triangle_soup(mesh, triangles);
  return mesh;
}

// solid NAME / facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop /
// endfacet / ... / endsolid NAME; several solids in one file are read as one mesh.
PolygonMesh parse_ascii(std::string_view text, const MeshLimits& limits) {
  enum class State { kOutside, kInSolid, kInFacet, kInLoop, kLoopClosed };
  State state = State::kOutside;
  TextReader reader(text, "STL");
  PolygonMesh mesh;
  size_t solids = 0, loop_corners = 0;
  auto expect = [&](State wanted, std::string_view keyword, const char* where) {
    if (state != wanted) reader.fail("'" + std::string(keyword) + "' " + where);
  };
  while (reader.next_line()) {
    const std::string_view keyword = reader.token();
    if (keyword.empty()) continue;
    if (keyword == "solid") {
      expect(State::kOutside, keyword, "inside a solid (missing 'endsolid')");
      state = State::kInSolid;
      ++solids;
      continue;  // the rest of the line is the solid's name
    }
    if (solids == 0) reader.fail("expected 'solid', found '" + std::string(keyword) + "'");
    if (keyword == "facet") {
      expect(State::kInSolid, keyword, "outside a solid or inside another facet");
      state = State::kInFacet;
      continue;  // "normal nx ny nz": orientation comes from the corner order
    } else if (keyword == "outer") {
      expect(State::kInFacet, keyword, "outside a facet");
      if (reader.token() != "loop") reader.fail("expected 'outer loop'");
      state = State::kInLoop;
      loop_corners = 0;
    } else if (keyword == "vertex") {
      expect(State::kInLoop, keyword, "outside an 'outer loop'");
      if (++loop_corners > 3) reader.fail("a facet with more than 3 vertices");
      if (loop_corners == 1) check_triangle_cap(mesh.positions.size() / 3 + 1, limits);
      Vec3 p;
      p.x = reader.number("x");
      p.y = reader.number("y");
      p.z = reader.number("z");
      mesh.positions.push_back(p);
    } else if (keyword == "endloop") {
      expect(State::kInLoop, keyword, "without 'outer loop'");
      if (loop_corners != 3)
        reader.fail("a facet needs 3 vertices, found " + std::to_string(loop_corners));
      state = State::kLoopClosed;
    } else if (keyword == "endfacet") {
      expect(State::kLoopClosed, keyword, "before 'endloop'");
      state = State::kInSolid;
    } else if (keyword == "endsolid") {
      expect(State::kInSolid, keyword, "inside a facet");
      state = State::kOutside;
      continue;  // the name again
    } else {
      reader.fail("unexpected '" + std::string(keyword) + "'");
    }
    if (!reader.token().empty())
      reader.fail("unexpected text after '" + std::string(keyword) + "'");
  }
  if (solids == 0) reader.fail("no 'solid' (an empty file?)");
  if (state != State::kOutside) reader.fail("the file ends before 'endsolid'");
  if (mesh.positions.size() > std::numeric_limits<uint32_t>::max())
    reader.fail("more corners than 32-bit indices can hold");
  make_triangle_soup(mesh, mesh.positions.size() / 3);
  return mesh;
}

}  // namespace

bool is_binary_stl(std::string_view bytes) {
  return bytes.size() >= kHeaderBytes && binary_size_for(declared_triangles(bytes)) == bytes.size();
}

PolygonMesh parse_stl(std::string_view bytes, const MeshLimits& limits) {
  PolygonMesh mesh;
  if (is_binary_stl(bytes)) {
    mesh = parse_binary(bytes, limits);
  } else if (begins_with_solid(bytes)) {
    try {
      mesh = parse_ascii(bytes, limits);
    } catch (const InputError& e) {
      if (bytes.size() < kHeaderBytes || e.check() != "parse") throw;
      // A binary file whose header begins with "solid" and whose size is off lands here.
      const uint32_t count = declared_triangles(bytes);
      throw InputError("parse", std::string(e.what()) + " (read as ASCII STL because it " +
                                    "begins with 'solid'; as binary STL its header declares " +
                                    std::to_string(count) + " triangles, which need " +
                                    std::to_string(binary_size_for(count)) + " bytes, but it has " +
                                    std::to_string(bytes.size()) + ")");
    }
  } else if (bytes.size() < kHeaderBytes) {
    fail("a " + std::to_string(bytes.size()) +
         "-byte file is too short for binary STL (an 84-byte header) and does not begin with "
         "'solid' (ASCII STL)");
  } else {
    const uint32_t count = declared_triangles(bytes);
    fail("the binary header declares " + std::to_string(count) +
         " triangles, which need 84 + 50 x " + std::to_string(count) + " = " +
         std::to_string(binary_size_for(count)) + " bytes, but the file has " +
         std::to_string(bytes.size()) + " (and it does not begin with 'solid', as ASCII STL does)");
  }
  reject_non_finite(mesh);
  return mesh;
}

}  // namespace spheremap
