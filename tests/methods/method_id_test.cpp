// The registry's table of names: every method once, its names, its EXR values old and new, and
// the form a session's slices give it.
#include "slicecap/methods/method_id.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include "slicecap/methods/errors.hpp"

namespace slicecap::methods {
namespace {

using ::testing::HasSubstr;

const std::vector<MethodId> kAll{MethodId::B,       MethodId::A,       MethodId::Uniform,
                                 MethodId::AGamma,  MethodId::UniformGamma, MethodId::Halfway,
                                 MethodId::Prior,   MethodId::BCells,
                                 MethodId::PriorCells};

SliceSet slicesOf(std::initializer_list<SliceId> ids) {
  SliceSet slices;
  for (const SliceId& id : ids)
    slices.add(id, {{30, 10}, {30, 25}, Rgb::gray(0.1f)});
  return slices;
}

TEST(MethodId, TheTableHasEveryMethodOnceInEnumOrder) {
  ASSERT_EQ(methodTable().size(), kAll.size());
  std::set<std::string_view> names, exrValues;
  for (std::size_t k = 0; k < kAll.size(); ++k) {
    const MethodInfo& info = methodTable()[k];
    EXPECT_EQ(info.id, kAll[k]);
    EXPECT_EQ(&methodInfo(kAll[k]), &info);
    EXPECT_TRUE(names.insert(info.cliName).second) << info.cliName;
    EXPECT_TRUE(exrValues.insert(info.exrName).second) << info.exrName;
    if (!info.isotropicExrName.empty()) {
      EXPECT_TRUE(exrValues.insert(info.isotropicExrName).second) << info.isotropicExrName;
    }
    // The CLI name is also a file name in a session's folder: the protocol's alphabet.
    EXPECT_EQ(info.cliName.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-"),
              std::string_view::npos);
  }
}

TEST(MethodId, NamesReadBackAndAnUnknownOneListsTheKnown) {
  for (MethodId id : kAll) {
    EXPECT_EQ(parseMethodName(cliName(id)), id);
    EXPECT_EQ(methodNamed(cliName(id)), id);
  }
  EXPECT_EQ(parseMethodName("B"), std::nullopt);
  EXPECT_EQ(methodNames(),
            "b, a, uniform, a-gamma, uniform-gamma, halfway, prior, b-cells, prior-cells");
  try {
    methodNamed("nosuch");
    FAIL() << "an unknown name was accepted";
  } catch (const MethodError& error) {
    EXPECT_THAT(error.what(), HasSubstr("unknown method 'nosuch' (known: b, a,"));
  }
}

TEST(MethodId, EachFormHasTheValueTheFileFormatDocuments) {
  EXPECT_EQ(exrMethodValue(MethodId::B, false), "B");
  EXPECT_EQ(exrMethodValue(MethodId::B, true), "B-isotropic");
  EXPECT_EQ(exrMethodValue(MethodId::A, true), "A-isotropic");
  EXPECT_EQ(exrMethodValue(MethodId::AGamma, true), "A-gamma-isotropic");
  EXPECT_EQ(exrMethodValue(MethodId::Halfway, true), "halfway-isotropic");
  EXPECT_EQ(exrMethodValue(MethodId::Prior, false), "prior");
  EXPECT_EQ(exrMethodValue(MethodId::Prior, true), "prior-isotropic");
  EXPECT_EQ(exrMethodValue(MethodId::BCells, false), "B-cells");
  EXPECT_EQ(exrMethodValue(MethodId::PriorCells, true), "prior-cells-isotropic");
  // The uniform baseline has no isotropic form: it ignores --isotropic.
  EXPECT_EQ(exrMethodValue(MethodId::Uniform, true), "uniform-RBF");
  EXPECT_EQ(exrMethodValue(MethodId::UniformGamma, false), "uniform-RBF-gamma");
}

TEST(MethodId, ReadsTheValuesBothWritersWroteBefore) {
  for (MethodId id : kAll)
    for (bool isotropic : {false, true}) {
      const std::optional<ExrMethod> read = parseExrMethodValue(exrMethodValue(id, isotropic));
      ASSERT_TRUE(read) << exrMethodValue(id, isotropic);
      EXPECT_EQ(read->id, id);
      const bool hasForm = !methodInfo(id).isotropicExrName.empty();
      EXPECT_EQ(read->isotropic, isotropic && hasForm);
    }
  // What slicecapd's export wrote before: the CLI name, which does not say the form.
  const std::optional<ExrMethod> oldB = parseExrMethodValue("b");
  ASSERT_TRUE(oldB);
  EXPECT_EQ(oldB->id, MethodId::B);
  EXPECT_EQ(oldB->isotropic, std::nullopt);
  ASSERT_TRUE(parseExrMethodValue("a-gamma"));
  EXPECT_EQ(parseExrMethodValue("a-gamma")->id, MethodId::AGamma);
  EXPECT_EQ(parseExrMethodValue("uniform")->id, MethodId::Uniform);
  // "prior" is both; as an EXR value it says the form.
  EXPECT_EQ(parseExrMethodValue("prior")->isotropic, false);
  EXPECT_EQ(parseExrMethodValue("analytic"), std::nullopt);  // `slicecap generate`'s
  EXPECT_EQ(parseExrMethodValue(""), std::nullopt);
}

TEST(MethodId, ASessionWithoutAxialSweepsGivesTheSliceMethodsTheirIsotropicForm) {
  const SliceSet diagonal = slicesOf({{SliceKind::Diagonal, {30, 30}},
                                      {SliceKind::Diagonal, {75, 75}}});
  const SliceSet mixed = slicesOf({{SliceKind::Diagonal, {30, 30}}, {SliceKind::Axial, {30, 30}}});
  for (MethodId id : {MethodId::B, MethodId::A, MethodId::AGamma, MethodId::Halfway}) {
    EXPECT_TRUE(sessionTakesIsotropicForm(id, diagonal)) << cliName(id);
    EXPECT_FALSE(sessionTakesIsotropicForm(id, mixed)) << cliName(id);
  }
  // The prior reads any subset as it is; the uniform baseline has no isotropic form.
  for (MethodId id : {MethodId::Prior, MethodId::Uniform, MethodId::UniformGamma})
    EXPECT_FALSE(sessionTakesIsotropicForm(id, diagonal)) << cliName(id);
}

}  // namespace
}  // namespace slicecap::methods
