// The reject reasons' stable names: the status, the reports and old journals count by them.
#include "slicecap/capture/reject_reason.hpp"

#include <gtest/gtest.h>

#include <set>
#include <sstream>
#include <string>

namespace slicecap::capture {
namespace {

TEST(RejectReason, EveryReasonHasItsOwnNameAndParsesBack) {
  std::set<std::string> names;
  for (RejectReason reason : kRejectReasons) {
    const std::string name(toString(reason));
    EXPECT_NE(name, "unknown");
    EXPECT_TRUE(names.insert(name).second) << name << " twice";
    EXPECT_EQ(parseRejectReason(name), reason) << name;
  }
  EXPECT_EQ(names.size(), 11u);
  EXPECT_EQ(parseRejectReason("window occluded"), std::nullopt);
  EXPECT_EQ(parseRejectReason(""), std::nullopt);
}

TEST(RejectReason, TheNamesAreTheDocumentedOnesInAlphabeticalOrder) {
  // The order keeps per-reason counts (std::map by reason) listed as they were by name.
  const std::string expected[] = {"bad_frame",       "blurred",           "detection_deferred",
                                  "elevation_off",   "led_transition",    "no_ambient_frame",
                                  "pose_residual",   "room_light_unseen", "too_few_markers",
                                  "window_clipped",  "window_occluded"};
  std::size_t k = 0;
  for (RejectReason reason : kRejectReasons) {
    ASSERT_LT(k, std::size(expected));
    EXPECT_EQ(toString(reason), expected[k++]);
  }
  std::ostringstream out;
  out << RejectReason::WindowOccluded;
  EXPECT_EQ(out.str(), "window_occluded");
}

}  // namespace
}  // namespace slicecap::capture
