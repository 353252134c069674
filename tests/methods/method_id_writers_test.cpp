// End-to-end: both writers of an ABRDF EXR put the same `slicecap:method` in the same situation:
// `slicecap reconstruct` on a session's slices and slicecapd's export of that session, with the
// reconstruction slicecapd's main injects (methods::runForSession).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "../support/cli_runner.hpp"
#include "../support/test_support.hpp"
#include "slicecap/daemon/session_manager.hpp"
#include "slicecap/io/abrdf_exr.hpp"
#include "slicecap/methods/methods.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::methods {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// What lib/rig's MethodTables::reconstruct gives the daemon.
Abrdf slicecapdReconstruct(const SliceSet& slices, const std::string& method) {
  return runForSession(methodNamed(method), slices).table;
}

std::string methodAttribute(const fs::path& exr) {
  io::ExrAttributes attributes;
  io::readAbrdfExr(exr, &attributes);
  return attributes.at("method");
}

class WritersAgree : public ::testing::Test {
 protected:
  // A session of brushed steel's slices of `kinds`, swept into a fresh daemon storage.
  void sweep(const std::vector<SliceKind>& kinds) {
    const SliceSet all =
        recon::extractSlices(models::tabulate(*models::findMaterial("brushed-steel-30")));
    ASSERT_TRUE(std::holds_alternative<json>(
        manager_.handle(control::SessionNew{"steel", std::string("steel")})));
    std::uint64_t frame = 0;
    for (const Slice& slice : all.slices()) {
      if (std::find(kinds.begin(), kinds.end(), slice.id.kind) == kinds.end()) continue;
      ASSERT_TRUE(std::holds_alternative<json>(manager_.handle(control::SweepStart{slice.id})));
      for (const SliceSample& s : slice.samples) {
        ++frame;
        ASSERT_TRUE(manager_.acceptSample(
            {std::int64_t(frame) * 33000, frame, s.light, s.view, s.value}));
      }
      ASSERT_TRUE(std::holds_alternative<json>(manager_.handle(control::SweepStop{})));
    }
  }

  // The daemon's export with `method` (its default without one): the table's attribute.
  std::string daemonWrites(const std::optional<std::string>& method) {
    const auto reply = manager_.handle(control::Export{std::nullopt, exported_.string(), method});
    if (const auto* error = std::get_if<control::ProtocolError>(&reply)) {
      ADD_FAILURE() << error->message;
      return "";
    }
    const std::string used = std::get<json>(reply)["method"];
    return methodAttribute(exported_ / ("steel-abrdf-" + used + ".exr"));
  }

  // `slicecap reconstruct` of the slices that export wrote, with `options`.
  std::string cliWrites(const std::vector<std::string>& options) {
    const fs::path out = root_ / "cli.exr";
    std::vector<std::string> args{"reconstruct", (exported_ / "steel-slices.csv").string(), "-o",
                                  out.string()};
    args.insert(args.end(), options.begin(), options.end());
    const test::CliResult r = test::runSlicecap(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return r.code == 0 ? methodAttribute(out) : "";
  }

  // One fresh folder per test (freshTempDir() empties it on every call): the daemon's storage,
  // its export and the CLI's table in it.
  fs::path root_ = test::freshTempDir();
  fs::path exported_ = root_ / "export";
  daemon::SessionManager manager_{root_ / "storage", slicecapdReconstruct};
};

TEST_F(WritersAgree, OnEveryMeasuredSlice) {
  sweep({SliceKind::Axial, SliceKind::Diagonal});
  const std::string daemon = daemonWrites(std::nullopt);  // all eight slices: Method B
  EXPECT_EQ(daemon, "B");
  EXPECT_EQ(cliWrites({}), daemon);
  EXPECT_EQ(daemonWrites(std::string("halfway")), "halfway");
  EXPECT_EQ(cliWrites({"--method", "halfway"}), "halfway");
}

TEST_F(WritersAgree, OnTheDiagonalSlicesOfAnIsotropicMaterial) {
  // The session without axial sweeps: the daemon takes the isotropic form, as the CLI with
  // --isotropic (without it the CLI refuses: docs/capture-gates.md).
  sweep({SliceKind::Diagonal});
  const std::string daemon = daemonWrites(std::string("b"));
  EXPECT_EQ(daemon, "B-isotropic");
  EXPECT_EQ(cliWrites({"--isotropic"}), daemon);
  EXPECT_EQ(daemonWrites(std::string("halfway")), "halfway-isotropic");
  EXPECT_EQ(cliWrites({"--method", "halfway", "--isotropic"}), "halfway-isotropic");
}

TEST_F(WritersAgree, OnASessionThatLacksSlicesWithThePrior) {
  sweep({SliceKind::Diagonal});
  // Not all eight slices: the daemon's default is the prior on every window cell, which reads
  // the subset as it is (the CLI reads the export's slice CSV, which keeps no cells, by the same
  // method and says so in the same words).
  const std::string daemon = daemonWrites(std::nullopt);
  EXPECT_EQ(daemon, "prior-cells");
  EXPECT_EQ(cliWrites({"--method", "prior-cells"}), daemon);
  EXPECT_EQ(daemonWrites(std::string("prior")), "prior");
  EXPECT_EQ(cliWrites({"--method", "prior"}), "prior");
}

}  // namespace
}  // namespace slicecap::methods
