// Caps on a mesh read from untrusted bytes, checked against the counts a file declares
// before anything is allocated for them (the service passes its max_vertices and
// max_faces; over either: InputError("too_large"), which it answers 413).
#pragma once

#include <cstddef>
#include <cstdint>

namespace spheremap {

struct MeshLimits {
  size_t max_vertices = SIZE_MAX;
  size_t max_triangles = SIZE_MAX;  // an n-gon counts n - 2
};

}  // namespace spheremap
