// Thin two-sided shells with slits (tests/thin_shells.h): the cut envelopes of open sheets,
// closed, manifold and genus 0; the default map certifies each (issue "Reach I" item 6).
// Before the squeezed stars were relieved (core/map/coarse_to_fine.cpp), none of the three
// was certified within 60 s.
#include <gtest/gtest.h>

#include "core/map/certification.h"
#include "core/map/pipeline.h"
#include "core/mesh/topology.h"
#include "core/prepare/envelope.h"
#include "tests/thin_shells.h"

namespace spheremap {
namespace {

void expect_cut_envelope_certified(size_t k) {
  const testing::NamedMesh sheet = testing::open_sheets().at(k);
  SCOPED_TRACE(sheet.name);
  EnvelopeOptions cut;
  cut.rule = EnvelopeRule::kCut;
  const Envelope envelope = build_envelope(sheet.mesh, cut);
  // A shell with slits: handles were cut, and it is about 3 voxels thick.
  EXPECT_EQ(envelope.report.rule, "cut");
  EXPECT_GT(envelope.report.handles_cut, 10u);
  ASSERT_NO_THROW(require_mappable(analyze_topology(envelope.mesh)));
  const MappedMesh mapped = map_mesh(envelope.mesh, {}, {});
  const Certification verdict = certify(mapped, mapped.float32_check);
  EXPECT_TRUE(verdict.certified) << verdict.detail;
}

TEST(ThinShells, FingersCutEnvelopeMapsCertified) {
  expect_cut_envelope_certified(0);
}
TEST(ThinShells, PerforatedCutEnvelopeMapsCertified) {
  expect_cut_envelope_certified(1);
}
TEST(ThinShells, SpiralCutEnvelopeMapsCertified) {
  expect_cut_envelope_certified(2);
}

// The fewest-voxels rule fills the same sheets' pinholes instead (fewer voxels changed).
TEST(ThinShells, TheDefaultRuleFillsThePinholes) {
  const Envelope envelope = build_envelope(testing::open_sheets().at(0).mesh, {});
  EXPECT_EQ(envelope.report.rule, "fill");
  EXPECT_EQ(envelope.report.handles_cut, 0u);
}

}  // namespace
}  // namespace spheremap
