// The Bonn grid: ring layout, index round trips and the file-name anchors of docs/method.md §1.1.
#include "slicecap/core/grid.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <set>

#include "slicecap/core/angles.hpp"
#include "slicecap/core/core_error.hpp"

namespace slicecap {
namespace {

TEST(BonnGrid, HasEightyOneDirectionsInSixRings) {
  int total = 0;
  for (const Ring& ring : bonn::kRings) {
    EXPECT_EQ(ring.firstIndex, total);
    total += ring.count;
  }
  EXPECT_EQ(total, 81);
  EXPECT_EQ(bonn::kRings[5].stepDeg(), 15.0);
  EXPECT_EQ(bonn::kRings[4].stepDeg(), 18.0);
}

TEST(BonnGrid, IndexAndDirectionRoundTrip) {
  std::set<std::pair<double, double>> seen;
  for (int i = 0; i < bonn::kDirectionCount; ++i) {
    const Direction d = bonn::direction(i);
    EXPECT_EQ(bonn::indexOf(d), i);
    EXPECT_TRUE(seen.insert({d.thetaDeg, d.phiDeg}).second) << "duplicate direction at " << i;
    EXPECT_GE(d.phiDeg, 0.0);
    EXPECT_LT(d.phiDeg, 360.0);
  }
}

TEST(BonnGrid, CosinesFollowEachDirectionsRing) {
  EXPECT_DOUBLE_EQ(bonn::cosines()[0], 1.0);
  for (const Ring& ring : bonn::kRings) {
    for (int k = 0; k < ring.count; ++k)
      EXPECT_DOUBLE_EQ(bonn::cosines()[std::size_t(ring.index(k))],
                       std::cos(degToRad(double(ring.thetaDeg))));
  }
}

TEST(BonnGrid, MatchesTheUbo2003FileNameAnchors) {
  // "00008 tl000 pl000 tv030 pv030": view (30, 30) is index 8.
  EXPECT_EQ(bonn::indexOf({30, 30}), 8);
  // "00162 tl015 pl060 tv000 pv000": light (15, 60) is index 2.
  EXPECT_EQ(bonn::indexOf({15, 60}), 2);
  EXPECT_EQ(bonn::indexOf({75, 345}), 80);
  EXPECT_EQ(bonn::indexOf({0, 123}), 0) << "the pole ignores azimuth";
  EXPECT_EQ(bonn::indexOf({45, 360 + 20}), 20) << "azimuths are wrapped";
}

TEST(BonnGrid, RejectsDirectionsOffTheGrid) {
  EXPECT_THROW(bonn::indexOf({30, 15}), slicecap::CoreError);
  EXPECT_THROW(bonn::indexOf({40, 0}), slicecap::CoreError);
  EXPECT_THROW(bonn::direction(81), std::out_of_range);
  EXPECT_THROW(bonn::direction(-1), std::out_of_range);
  EXPECT_THROW(bonn::ringAt(50), slicecap::CoreError);
  EXPECT_FALSE(bonn::ringOfElevation(29.9).has_value());
}

TEST(Directions, VectorRoundTrip) {
  for (int i = 0; i < bonn::kDirectionCount; ++i) {
    const Direction d = bonn::direction(i);
    const UnitVector v = toUnitVector(d);
    EXPECT_NEAR(v.x * v.x + v.y * v.y + v.z * v.z, 1.0, 1e-12);
    const Direction back = toDirection(v);
    EXPECT_NEAR(back.thetaDeg, d.thetaDeg, 1e-9);
    if (d.thetaDeg > 0) {
      EXPECT_NEAR(azimuthDifferenceDeg(back.phiDeg, d.phiDeg), 0.0, 1e-9);
    }
  }
  EXPECT_THROW(toDirection({0, 0, 0}), slicecap::CoreError);
}

TEST(Directions, AngleBetweenThem) {
  EXPECT_NEAR(angleBetweenDeg({30, 0}, {30, 0}), 0.0, 1e-6);
  EXPECT_NEAR(angleBetweenDeg({0, 0}, {75, 123}), 75.0, 1e-9);
  EXPECT_NEAR(angleBetweenDeg({90, 0}, {90, 180}), 180.0, 1e-9);
  EXPECT_NEAR(angleBetweenDeg({45, 10}, {45, 100}), 60.0, 1e-9);  // cos = 1/2
}

TEST(Angles, WrapAndDifference) {
  EXPECT_DOUBLE_EQ(wrapDeg360(-15.0), 345.0);
  EXPECT_DOUBLE_EQ(wrapDeg360(720.0), 0.0);
  EXPECT_LT(wrapDeg360(-1e-14), 360.0);
  EXPECT_DOUBLE_EQ(azimuthDifferenceDeg(10.0, 350.0), 20.0);
  EXPECT_DOUBLE_EQ(azimuthDifferenceDeg(350.0, 10.0), -20.0);
  EXPECT_NEAR(radToDeg(degToRad(75.0)), 75.0, 1e-12);
}

TEST(Angles, WrapTakesTheShortcutsOnlyWhereFmodGivesTheSameBits) {
  auto byFmod = [](double deg) {
    double wrapped = std::fmod(deg, 360.0);
    if (wrapped < 0.0) wrapped += 360.0;
    return wrapped >= 360.0 ? 0.0 : wrapped;
  };
  for (double deg :
       {0.0, -0.0, 1e-300, 172.5, std::nextafter(360.0, 0.0), 360.0, std::nextafter(360.0, 720.0),
        547.5, std::nextafter(720.0, 0.0), 720.0, 1e6 + 0.1, -1e-14, -15.0, -360.0, -1e6 - 0.1}) {
    const double got = wrapDeg360(deg);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(byFmod(deg))) << deg;
    EXPECT_GE(got, 0.0) << deg;
    EXPECT_LT(got, 360.0) << deg;
  }
}

}  // namespace
}  // namespace slicecap
