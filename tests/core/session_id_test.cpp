#include "slicecap/core/session_id.hpp"

#include <gtest/gtest.h>

#include <string>

namespace slicecap {
namespace {

TEST(SessionId, TakesLowerCaseLettersDigitsUnderscoresAndDashesUpTo64) {
  EXPECT_TRUE(isValidSessionId("red-felt_2"));
  EXPECT_TRUE(isValidSessionId("7"));
  EXPECT_TRUE(isValidSessionId(std::string(64, 'a')));
}

TEST(SessionId, RefusesWhatCouldReadAsAnOptionOrLeaveTheStorageFolder) {
  for (const std::string id : {"", "-x", "_x", "Red", "a.b", "..", "a/b", "a b", "é"})
    EXPECT_FALSE(isValidSessionId(id)) << id;
  EXPECT_FALSE(isValidSessionId(std::string(65, 'a')));
}

}  // namespace
}  // namespace slicecap
