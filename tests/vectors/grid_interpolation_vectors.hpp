// Shared test vectors for interpolating a table at arbitrary directions: built here from the C++
// `evaluate`, committed as JSON, and read by the Python package's tests so both agree.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/core_error.hpp"
#include "slicecap/core/grid_interpolation.hpp"

namespace slicecap::vectors {

// The table is an integer hash of (light, view, channel) rather than anything smooth, so that a
// reader that mixes up rows, columns, channels or ring neighbours cannot agree by accident.
inline constexpr int kMultipliers[3] = {7919, 104729, 1299709};
inline constexpr int kModulus = 1000;

inline Abrdf hashTable() {
  Abrdf table;
  for (int l = 0; l < Abrdf::kDirections; ++l) {
    for (int v = 0; v < Abrdf::kDirections; ++v) {
      for (int c = 0; c < 3; ++c) {
        const int k = (l * kMultipliers[0] + v * kMultipliers[1] + c * kMultipliers[2]) % kModulus;
        table.channel(l, v, c) = static_cast<float>((k + 1) / double(kModulus));
      }
    }
  }
  return table;
}

// A portable generator (std::uniform_real_distribution differs between standard libraries).
class Lcg {
 public:
  explicit Lcg(std::uint32_t seed) : state_(seed) {}
  double uniform(double lo, double hi) {
    state_ = state_ * 1664525u + 1013904223u;
    return lo + (hi - lo) * (state_ / 4294967296.0);
  }

 private:
  std::uint32_t state_;
};

struct Case {
  std::string kind;
  Direction light, view;
};

inline std::vector<Case> cases() {
  std::vector<Case> all;
  for (auto [l, v] : {std::pair{0, 0}, {3, 40}, {18, 7}, {57, 80}, {80, 57}, {44, 23}})
    all.push_back({"grid", bonn::direction(l), bonn::direction(v)});
  all.push_back({"azimuth", {30, 15}, {75, 352.5}});
  all.push_back({"azimuth", {45, 137.3}, {60, 9}});
  all.push_back({"azimuth", {15, 359.999}, {30, 0.001}});
  all.push_back({"elevation", {37.5, 0}, {52.5, 90}});
  all.push_back({"elevation", {22.5, 200}, {67.5, 301.7}});
  all.push_back({"pole", {5, 100}, {0, 270}});
  all.push_back({"pole", {0, 33}, {14.9, 181}});
  all.push_back({"wrap", {30, -15}, {45, 370}});
  all.push_back({"wrap", {60, -725.4}, {75, 1080}});
  all.push_back({"clamp", {75, 7.5}, {80, 7.5}});
  all.push_back({"clamp", {89.9, 123.4}, {90, 300}});
  all.push_back({"clamp", {120, 10}, {45, 10}});
  Lcg random(20130211);
  for (int i = 0; i < 40; ++i) {
    const Direction light{random.uniform(0, 90), random.uniform(-360, 720)};
    const Direction view{random.uniform(0, 90), random.uniform(-360, 720)};
    all.push_back({"random", light, view});
  }
  return all;
}

// Directions `evaluate` must reject (slicecap::CoreError); NaN cannot be written in JSON.
inline std::vector<Case> invalidCases() {
  return {{"negative-elevation", {-1, 0}, {30, 0}}, {"negative-elevation", {30, 0}, {-0.5, 90}}};
}

inline nlohmann::json directionJson(const Direction& d) {
  return nlohmann::json::array({d.thetaDeg, d.phiDeg});
}

/// \brief The whole vector file: the table's definition, cases with expected RGB, invalid cases.
inline nlohmann::json build() {
  const Abrdf table = hashTable();
  nlohmann::json out;
  out["about"] =
      "Interpolation of an 81 x 81 Bonn-grid table at arbitrary directions, computed by "
      "slicecap::evaluate (lib/core/grid_interpolation). Directions are [theta_deg, phi_deg]. "
      "Regenerate with build/tests/make_grid_interpolation_vectors; "
      "tests/vectors/grid_interpolation_vectors_test.cpp checks this file against the C++ code.";
  out["table"] = {
      {"formula",
       "value[light][view][c] = float32(((light*m0 + view*m1 + c*m2) % modulus + 1) / modulus)"},
      {"multipliers", kMultipliers},
      {"modulus", kModulus}};
  nlohmann::json list = nlohmann::json::array();
  for (const Case& c : cases()) {
    const Rgb value = evaluate(table, c.light, c.view);
    list.push_back({{"kind", c.kind},
                    {"light", directionJson(c.light)},
                    {"view", directionJson(c.view)},
                    {"rgb", {value.r(), value.g(), value.b()}}});
  }
  out["cases"] = list;
  nlohmann::json invalid = nlohmann::json::array();
  for (const Case& c : invalidCases()) {
    invalid.push_back(
        {{"kind", c.kind}, {"light", directionJson(c.light)}, {"view", directionJson(c.view)}});
  }
  out["invalid"] = invalid;
  return out;
}

}  // namespace slicecap::vectors
