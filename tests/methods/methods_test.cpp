// The registry's runs: each method by its id and name, and the EXR name each run reports is the
// table's (method_id.hpp), in both forms.
#include "slicecap/methods/methods.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "slicecap/methods/errors.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/slice_extraction.hpp"
#include "slicecap/recon/uniform_sampling.hpp"

namespace slicecap::methods {
namespace {

using ::testing::HasSubstr;

const SliceSet& brushedSteelSlices() {
  static const SliceSet slices =
      recon::extractSlices(models::tabulate(*models::findMaterial("brushed-steel-30")));
  return slices;
}

SliceSet diagonalOnly(const SliceSet& slices) {
  SliceSet diagonal;
  for (const Slice& slice : slices.slices())
    if (slice.id.kind == SliceKind::Diagonal)
      for (const SliceSample& sample : slice.samples)
        diagonal.add(slice.id, sample);
  return diagonal;
}

TEST(Methods, EveryMethodOnceInTheTablesOrder) {
  const std::vector<Method>& methods = reconstructionMethods();
  ASSERT_EQ(methods.size(), methodTable().size());
  for (std::size_t k = 0; k < methods.size(); ++k) {
    EXPECT_EQ(methods[k].id, methodTable()[k].id);
    EXPECT_EQ(methods[k].name, methodTable()[k].cliName);
    EXPECT_EQ(&findMethod(methods[k].id), &methods[k]);
    EXPECT_EQ(&findMethod(methods[k].name), &methods[k]);
    EXPECT_EQ(methods[k].acquisition == Acquisition::UniformGrid13,
              methodTable()[k].reads == SliceSubset::PointSamples);
  }
  EXPECT_THROW(findMethod(std::string("B")), MethodError);
}

TEST(Methods, HelpListsEachNameInOneColumn) {
  const std::string help = methodHelpLines();
  for (const Method& m : reconstructionMethods())
    EXPECT_THAT(help, HasSubstr("  " + m.name + " ")) << help;
  // The halfway summary's second line starts in the summaries' column (name width 13 + 4).
  EXPECT_THAT(help, HasSubstr("\n" + std::string(17, ' ') + "measured ones in halfway angle"));
}

TEST(Methods, EachRunNamesItsTableByTheRegistrysValue) {
  const SliceSet& slices = brushedSteelSlices();
  for (MethodId id : {MethodId::B, MethodId::Halfway}) {
    MethodOptions options;
    EXPECT_EQ(findMethod(id).run(slices, options).exrMethodName, exrMethodValue(id, false));
    options.isotropic = true;
    EXPECT_EQ(findMethod(id).run(diagonalOnly(slices), options).exrMethodName,
              exrMethodValue(id, true));
  }
  const SliceSet points = recon::extractUniformSamples(
      models::tabulate(*models::findMaterial("brushed-steel-30")),
      recon::kUniformBaselineDirections);
  MethodOptions isotropic;
  isotropic.isotropic = true;
  EXPECT_EQ(findMethod(MethodId::Uniform).run(points, isotropic).exrMethodName, "uniform-RBF");
}

TEST(Methods, ASessionsRunTakesTheFormItsSlicesGive) {
  const SliceSet& slices = brushedSteelSlices();
  EXPECT_EQ(runForSession(MethodId::B, slices).exrMethodName, "B");
  const MethodRun isotropic = runForSession(MethodId::B, diagonalOnly(slices));
  EXPECT_EQ(isotropic.exrMethodName, "B-isotropic");
  // The same table as the isotropic form asked for by hand (`reconstruct --isotropic`).
  MethodOptions options;
  options.isotropic = true;
  const Abrdf byHand = findMethod(MethodId::B).run(diagonalOnly(slices), options).table;
  EXPECT_EQ(isotropic.table.at(20, 40).r(), byHand.at(20, 40).r());
  EXPECT_GT(byHand.at(20, 40).r(), 0.0f);
}

// b-cells is Method B on each slice's cell samples; a set without them (a slice CSV, ideal
// slices) gives Method B's table on the window centres, the paper's figures unchanged, and says so.
TEST(Methods, BCellsReadsTheCellSamplesAndWithoutThemIsMethodB) {
  const SliceSet& slices = brushedSteelSlices();
  const MethodRun b = findMethod(MethodId::B).run(slices, {});
  const MethodRun plain = findMethod(MethodId::BCells).run(slices, {});
  EXPECT_EQ(plain.exrMethodName, "B-cells");
  ASSERT_EQ(plain.warnings.size(), 1u);
  EXPECT_THAT(plain.warnings[0], HasSubstr("8 slices have no window cells"));
  for (int light = 0; light < 81; light += 7)
    for (int view = 0; view < 81; view += 5)
      EXPECT_EQ(plain.table.at(light, view).g(), b.table.at(light, view).g());
  // Cell samples twice the centres' on every slice: b-cells reads them, b does not.
  SliceSet withCells = slices;
  for (const Slice& slice : slices.slices())
    for (const SliceSample& sample : slice.samples)
      withCells.addCellSample(slice.id, {sample.light, sample.view, sample.value * 2.0});
  const MethodRun cells = findMethod(MethodId::BCells).run(withCells, {});
  EXPECT_TRUE(cells.warnings.empty());
  EXPECT_NEAR(cells.table.at(40, 60).g(), 2.0 * b.table.at(40, 60).g(),
              1e-3 * b.table.at(40, 60).g());
  EXPECT_EQ(findMethod(MethodId::B).run(withCells, {}).table.at(40, 60).g(),
            b.table.at(40, 60).g());
}

// prior-cells is the prior on the cells' reading: on the centres where there are no cells.
TEST(Methods, PriorCellsReadsTheCellSamplesAndWithoutThemIsThePrior) {
  const SliceSet& slices = brushedSteelSlices();
  const MethodRun prior = findMethod(MethodId::Prior).run(slices, {});
  const MethodRun plain = findMethod(MethodId::PriorCells).run(slices, {});
  EXPECT_EQ(plain.exrMethodName, "prior-cells");
  EXPECT_EQ(plain.table.at(40, 60).g(), prior.table.at(40, 60).g());
  EXPECT_THAT(plain.warnings.back(), HasSubstr("8 slices have no window cells"));
  SliceSet withCells = slices;
  for (const Slice& slice : slices.slices())
    for (const SliceSample& sample : slice.samples)
      withCells.addCellSample(slice.id, {sample.light, sample.view, sample.value * 2.0});
  EXPECT_GT(findMethod(MethodId::PriorCells).run(withCells, {}).table.at(40, 60).g(),
            1.5 * prior.table.at(40, 60).g());
}

// prior-cells fits every window cell by default (docs/method.md §9.4): cell frames at 2 x the
// cells' per-bin reading pull its table up; asked per bin, the frames are not read.
TEST(Methods, PriorCellsFitsEveryWindowCellUnlessAskedPerBin) {
  const SliceSet& slices = brushedSteelSlices();
  SliceSet withFrames = slices;
  for (const Slice& slice : slices.slices())
    for (const SliceSample& sample : slice.samples) {
      withFrames.addCellSample(slice.id, sample);
      withFrames.addCellFrame(slice.id, {{{sample.light, sample.view, sample.value * 2.0}, Rgb{}}});
    }
  const double prior = findMethod(MethodId::Prior).run(slices, {}).table.at(40, 60).g();
  const MethodRun everyCell = findMethod(MethodId::PriorCells).run(withFrames, {});
  EXPECT_GT(everyCell.table.at(40, 60).g(), 1.5 * prior);
  EXPECT_GT(everyCell.details["prior"]["frame_groups"].get<std::size_t>(), 0u);
  EXPECT_THAT(everyCell.lines, testing::Contains(HasSubstr("prior fitted to every window cell")));
  MethodOptions perBin;
  perBin.priorFitsEveryCell = false;
  const MethodRun perBinRun = findMethod(MethodId::PriorCells).run(withFrames, perBin);
  EXPECT_NEAR(perBinRun.table.at(40, 60).g(), prior, 1e-6 * prior);
  EXPECT_EQ(perBinRun.details["prior"]["frame_groups"].get<std::size_t>(), 0u);
  EXPECT_THAT(perBinRun.lines,
              testing::Not(testing::Contains(HasSubstr("prior fitted to every window cell"))));
}

}  // namespace
}  // namespace slicecap::methods
