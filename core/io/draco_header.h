// The sizes a Draco mesh stream declares, read from its header before anything is
// decoded: Draco allocates by the declared counts, so a few kilobytes can ask for
// gigabytes (measured: 5 MB became 3.5 GB) and its metadata reader recurses without a
// bound. Reading them first lets the caller refuse by its own caps. Internal to the glTF
// reader.
#pragma once

#include <cstdint>
#include <span>

namespace spheremap {

struct DracoCounts {
  uint64_t faces = 0;
  // Sequential encoding: the points; edgebreaker: the encoded vertices (decoded points
  // can add seam copies, at most 3 per face).
  uint64_t vertices = 0;
};

// Throws InputError("gltf") when the stream is not a Draco triangle mesh of bitstream
// version 2.2 (what KHR_draco_mesh_compression encoders write), or its header or
// metadata is malformed (sizes past the end, sub-metadata nested over 16 deep).
// A point cloud stream is refused saying how many points it holds.
DracoCounts read_draco_counts(std::span<const uint8_t> stream);

// The points a Draco point cloud stream (geometry type 0) declares, read from its header
// and metadata without decoding; throws InputError("gltf") when they are malformed.
uint64_t read_draco_point_count(std::span<const uint8_t> stream);

}  // namespace spheremap
