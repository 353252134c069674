// wholeNumberIn: only integer tokens within the range, never nlohmann's silent conversions.
#include "slicecap/io/json_numbers.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace slicecap::io {
namespace {

using nlohmann::json;

TEST(WholeNumberIn, ReadsIntegersWithinTheRange) {
  EXPECT_EQ(wholeNumberIn(json::parse("30"), 0, 89), 30);
  EXPECT_EQ(wholeNumberIn(json::parse("0"), 0, 89), 0);
  EXPECT_EQ(wholeNumberIn(json::parse("89"), 0, 89), 89);
  EXPECT_EQ(wholeNumberIn(json::parse("-5"), -10, 10), -5);
}

TEST(WholeNumberIn, RefusesWhatGetIntWouldConvertQuietly) {
  EXPECT_EQ(wholeNumberIn(json::parse("30.5"), 0, 89), std::nullopt);   // get<int>: 30
  EXPECT_EQ(wholeNumberIn(json::parse("30.0"), 0, 89), std::nullopt);   // a float token
  EXPECT_EQ(wholeNumberIn(json::parse("1e300"), 0, 89), std::nullopt);  // get<int>: UB
  EXPECT_EQ(wholeNumberIn(json::parse("\"30\""), 0, 89), std::nullopt);
  EXPECT_EQ(wholeNumberIn(json::parse("null"), 0, 89), std::nullopt);
  EXPECT_EQ(wholeNumberIn(json::parse("true"), 0, 1), std::nullopt);
}

TEST(WholeNumberIn, RefusesOutOfRangeWithoutWrapping) {
  EXPECT_EQ(wholeNumberIn(json::parse("90"), 0, 89), std::nullopt);
  EXPECT_EQ(wholeNumberIn(json::parse("-1"), 0, 89), std::nullopt);
  // 2^64 - 1 is -1 when read as int64: it must not pass a range that holds -1.
  EXPECT_EQ(wholeNumberIn(json::parse("18446744073709551615"), -10, 10), std::nullopt);
  constexpr auto kMax = std::numeric_limits<std::int64_t>::max();
  constexpr auto kMin = std::numeric_limits<std::int64_t>::min();
  EXPECT_EQ(wholeNumberIn(json::parse("9223372036854775807"), kMin, kMax), kMax);
  EXPECT_EQ(wholeNumberIn(json::parse("9223372036854775808"), kMin, kMax), std::nullopt);
}

}  // namespace
}  // namespace slicecap::io
