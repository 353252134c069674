// Where the prior is found: the shipped model from the source tree, and SLICECAP_PRIOR used or an
// error naming it.
#include "slicecap/prior/prior_location.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "../support/test_support.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {
namespace {

TEST(PriorLocation, TheShippedPriorIsFoundFromTheSourceTree) {
  const PriorModel& model = defaultPriorModel();
  EXPECT_EQ(model.components(), 16);
  EXPECT_NE(model.provenance.find("MIT"), std::string::npos) << "the licence is named";
  EXPECT_LT(std::filesystem::file_size(locatePriorModel()), 2u << 20) << "under 2 MB";
}

// Sets an environment variable for one scope, restoring what was there.
class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) saved_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnvironment() {
    if (saved_) {
      ::setenv(name_, saved_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  const char* name_;
  std::optional<std::string> saved_;
};

TEST(PriorLocation, ASetSlicecapPriorIsUsedOrIsAnErrorNamingIt) {
  // A missing file or a directory in SLICECAP_PRIOR was silently passed over for the next place.
  const auto dir = test::freshTempDir();
  for (const std::filesystem::path& bad : {dir / "absent.bin", dir}) {
    const ScopedEnvironment prior("SLICECAP_PRIOR", bad.string());
    try {
      locatePriorModel();
      ADD_FAILURE() << bad << " was passed over";
    } catch (const PriorError& e) {
      EXPECT_NE(std::string(e.what()).find("SLICECAP_PRIOR=" + bad.string()), std::string::npos)
          << e.what();
    }
  }
  std::filesystem::copy_file(locatePriorModel(), dir / "mine.bin");
  const ScopedEnvironment prior("SLICECAP_PRIOR", (dir / "mine.bin").string());
  EXPECT_EQ(locatePriorModel(), dir / "mine.bin");
}

}  // namespace
}  // namespace slicecap::prior
