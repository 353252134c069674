// The per-texel reconstruction's choice of method: one of the registry's, and only those that
// solve a texel.
#include "slicecap/btf/btf_reconstruction.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "slicecap/btf/btf_error.hpp"

namespace slicecap::btf {
namespace {

using ::testing::HasSubstr;

TEST(BtfReconstruction, AMethodThatDoesNotSolveTexelsIsNamed) {
  const TextureGrid grid(2, {-1.0, -1.0, 1.0, 1.0});
  for (methods::MethodId id : {methods::MethodId::Halfway, methods::MethodId::Uniform,
                               methods::MethodId::AGamma}) {
    BtfReconstructionParams params;
    params.method = id;
    try {
      reconstructBtf(grid, {}, params);
      ADD_FAILURE() << methods::cliName(id) << " was accepted";
    } catch (const btf::BtfError& error) {
      EXPECT_THAT(error.what(), HasSubstr("method " + methods::cliName(id) +
                                          " does not reconstruct texels (b, a or prior do)"));
    }
  }
  // Method B is the default and one of them.
  EXPECT_EQ(BtfReconstructionParams{}.method, methods::MethodId::B);
  EXPECT_EQ(kTexelMethods.size(), 3u);
}

}  // namespace
}  // namespace slicecap::btf
