#include "tests/draco_writer.h"

#include <draco/mesh/mesh.h>

#include <stdexcept>

namespace spheremap::testing {

void add_draco_positions(draco::PointCloud& out, const std::vector<Vec3>& positions) {
  out.set_num_points(static_cast<uint32_t>(positions.size()));
  draco::GeometryAttribute attribute;
  attribute.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  const int id = out.AddAttribute(attribute, true, static_cast<uint32_t>(positions.size()));
  for (uint32_t i = 0; i < positions.size(); ++i) {
    const float f[3] = {static_cast<float>(positions[i].x), static_cast<float>(positions[i].y),
                        static_cast<float>(positions[i].z)};
    out.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), f);
  }
}

std::string drc_bytes(const PolygonMesh& mesh, draco::MeshEncoderMethod method) {
  draco::Mesh out;
  add_draco_positions(out, mesh.positions);
  out.SetNumFaces(mesh.face_count());
  for (uint32_t f = 0; f < mesh.face_count(); ++f) {
    draco::Mesh::Face face;
    for (int c = 0; c < 3; ++c) face[c] = draco::PointIndex(mesh.face(f)[c]);
    out.SetFace(draco::FaceIndex(f), face);
  }
  draco::Encoder encoder;
  encoder.SetEncodingMethod(method);
  draco::EncoderBuffer buffer;
  if (!encoder.EncodeMeshToBuffer(out, &buffer).ok())
    throw std::runtime_error("draco: the test mesh could not be encoded");
  return std::string(buffer.data(), buffer.size());
}

std::string drc_point_cloud_bytes(const std::vector<Vec3>& positions) {
  draco::PointCloud cloud;
  add_draco_positions(cloud, positions);
  draco::Encoder encoder;
  draco::EncoderBuffer buffer;
  if (!encoder.EncodePointCloudToBuffer(cloud, &buffer).ok())
    throw std::runtime_error("draco: the test point cloud could not be encoded");
  return std::string(buffer.data(), buffer.size());
}

}  // namespace spheremap::testing
