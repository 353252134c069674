// A session that lacks a measured slice: the missing slices named with their sweep commands, the
// prior instead, and an isotropic capture without --isotropic said rather than hidden.
#include "slicecap/methods/method_fallback.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::methods {
namespace {

using ::testing::HasSubstr;

SliceSet without(const SliceSet& slices, auto drop) {
  SliceSet kept;
  for (const Slice& slice : slices.slices())
    if (!drop(slice.id))
      for (const SliceSample& sample : slice.samples)
        kept.add(slice.id, sample);
  return kept;
}

const SliceSet& steel() {
  static const SliceSet slices =
      recon::extractSlices(models::tabulate(*models::findMaterial("brushed-steel-30")));
  return slices;
}

TEST(MethodFallback, NamesTheMissingSlicesAndTheirCommands) {
  const SliceId lost{SliceKind::Axial, {75, 30}};
  const SliceSet slices = without(steel(), [&](const SliceId& id) { return id == lost; });
  EXPECT_EQ(missingMeasuredSlices(slices, false), std::vector<SliceId>{lost});
  EXPECT_TRUE(missingMeasuredSlices(slices, true).empty()) << "the isotropic form reads no axial";
  EXPECT_EQ(sweepCommand(lost), "slicecap sweep start axial 75 30");
}

TEST(MethodFallback, AMissingSliceIsReconstructedWithThePriorAndSaidSo) {
  const SliceId lost{SliceKind::Diagonal, {30, 75}};
  const SliceSet slices = without(steel(), [&](const SliceId& id) { return id == lost; });
  const MethodRun run = runMethodOrPrior(findMethod(MethodId::B), slices, {});
  EXPECT_EQ(run.exrMethodName, "prior");
  ASSERT_FALSE(run.warnings.empty());
  EXPECT_THAT(run.warnings.front(), HasSubstr("method b needs every measured slice"));
  EXPECT_THAT(run.warnings.front(), HasSubstr("slicecap sweep start diagonal 30 75"));
  EXPECT_EQ(run.details["method_requested"], "b");
  // The cells' reading falls back to the prior on the cells' reading.
  EXPECT_EQ(runMethodOrPrior(findMethod(MethodId::BCells), slices, {}).exrMethodName,
            "prior-cells");
  // A method that reads any subset runs as asked.
  EXPECT_EQ(runMethodOrPrior(findMethod(MethodId::Prior), slices, {}).details.count(
                "method_requested"),
            0u);
}

TEST(MethodFallback, OnlyDiagonalSlicesWithoutIsotropicIsAnErrorNotThePrior) {
  const SliceSet diagonal =
      without(steel(), [](const SliceId& id) { return id.kind == SliceKind::Axial; });
  try {
    runMethodOrPrior(findMethod(MethodId::B), diagonal, {});
    FAIL() << "a diagonal-only capture was reconstructed without --isotropic";
  } catch (const recon::ReconstructionError& error) {
    EXPECT_THAT(error.what(), HasSubstr("only the diagonal slices were measured"));
  }
  MethodOptions isotropic;
  isotropic.isotropic = true;
  EXPECT_EQ(runMethodOrPrior(findMethod(MethodId::B), diagonal, isotropic).exrMethodName,
            "B-isotropic");
}

}  // namespace
}  // namespace slicecap::methods
