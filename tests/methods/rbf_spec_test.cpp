// RBF specs (`--rbf SPEC`): each key read into the options, printed back, and errors that name
// the key and the range.
#include "slicecap/methods/rbf_spec.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "slicecap/methods/errors.hpp"

namespace slicecap::methods {
namespace {

using ::testing::HasSubstr;

std::string errorOf(const std::string& spec) {
  MethodOptions options;
  try {
    applyRbfSpec(spec, options);
  } catch (const MethodError& error) {
    return error.what();
  }
  ADD_FAILURE() << "'" << spec << "' was accepted";
  return "";
}

TEST(RbfSpec, ReadsEveryKeyAndPrintsASpecThatReadsBack) {
  MethodOptions options;
  applyRbfSpec("kernel=r3,poly=linear,frame=absolute,gamma=4,r0=2", options);
  EXPECT_EQ(options.rbf.kernel, recon::RbfKernel::Cubic);
  EXPECT_EQ(options.rbf.polynomial, recon::RbfPolynomial::Linear);
  EXPECT_EQ(options.onionFrame, recon::OnionFrame::Absolute);
  EXPECT_DOUBLE_EQ(options.rbf.valueGamma, 4.0);
  EXPECT_DOUBLE_EQ(options.rbf.shapeScale, 2.0);
  const std::string printed = rbfSpec(options);
  EXPECT_EQ(printed, "kernel=r3,poly=linear,r0=2,frame=absolute,gamma=4");
  MethodOptions again;
  applyRbfSpec(printed, again);
  EXPECT_EQ(rbfSpec(again), printed);
}

TEST(RbfSpec, TheDefaultsAreMethodAs) {
  const MethodOptions options;
  EXPECT_EQ(options.rbf.valueGamma, recon::MethodAParams{}.rbf.valueGamma);
  MethodOptions applied;
  applyRbfSpec(rbfSpec(options), applied);
  EXPECT_EQ(rbfSpec(applied), rbfSpec(options));
}

TEST(RbfSpec, ABadSpecNamesItsKeyOrValue) {
  EXPECT_THAT(errorOf("kernel=gauss"), HasSubstr("--rbf: kernel 'gauss' is not one of mq, imq"));
  EXPECT_THAT(errorOf("poly=cubic"), HasSubstr("poly 'cubic'"));
  EXPECT_THAT(errorOf("frame=left"), HasSubstr("frame 'left'"));
  EXPECT_THAT(errorOf("r0=5"), HasSubstr("--rbf: r0 '5' is not a number in 0.01..4"));
  EXPECT_THAT(errorOf("r0=0.5x"), HasSubstr("r0 '0.5x'"));
  EXPECT_THAT(errorOf("gamma=0.5"), HasSubstr("gamma '0.5' is not a number in 1..1000"));
  EXPECT_THAT(errorOf("size=3"), HasSubstr("unknown key 'size'"));
  EXPECT_THAT(errorOf("kernel"), HasSubstr("'kernel' is not key=value"));
}

}  // namespace
}  // namespace slicecap::methods
