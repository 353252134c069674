// The halfway method: neighbour tables in halfway/difference angles, built once, applied per
// capture.
#include "slicecap/recon/halfway_method.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "slicecap/recon/argument_error.hpp"
#include "slicecap/recon/measured_subspaces.hpp"
#include "slicecap/recon/rbf_interpolant.hpp"

namespace slicecap::recon {
namespace {

// The halfway vector and the difference angle (radians) of a light/view pair.
struct HalfwayAngles {
  UnitVector half;
  double differenceRad = 0.0;
};

HalfwayAngles halfwayAngles(const TableEntry& entry, bool isotropic) {
  const UnitVector l = toUnitVector(bonn::direction(entry.light));
  const UnitVector v = toUnitVector(bonn::direction(entry.view));
  UnitVector h{l.x + v.x, l.y + v.y, l.z + v.z};
  const double length = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
  h = {h.x / length, h.y / length, h.z / length};
  const double cosDifference = std::clamp(l.x * h.x + l.y * h.y + l.z * h.z, -1.0, 1.0);
  // An isotropic material depends on the halfway elevation only: turn h to azimuth 0, so that
  // every rotation of a measured configuration is a neighbour.
  if (isotropic) h = {std::sqrt(std::max(0.0, 1.0 - h.z * h.z)), 0.0, h.z};
  return {h, std::acos(cosDifference)};
}

double foreshortening(const TableEntry& entry, double exponent) {
  const double cosI = std::cos(bonn::direction(entry.light).thetaDeg * M_PI / 180.0);
  const double cosV = std::cos(bonn::direction(entry.view).thetaDeg * M_PI / 180.0);
  return std::pow(cosI * cosV, exponent);
}

// A low percentile of one channel's measured values: the part every direction shares.
double diffuseFloor(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t k = values.size() / 50;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return std::max(0.0, values[k]);
}

}  // namespace

bool HalfwayParams::isValid(std::string* error) const {
  std::string reason;
  if (neighbours < 1)
    reason = "neighbours must be at least 1";
  else if (!(differenceWeight >= 0.0) || !std::isfinite(differenceWeight))
    reason = "differenceWeight must be finite and >= 0";
  else if (!std::isfinite(foreshorteningExponent))
    reason = "foreshorteningExponent must be finite";
  else if (!(std::isfinite(valueGamma) && valueGamma > 0.0))
    reason = "valueGamma must be positive";
  if (reason.empty()) return true;
  if (error) *error = reason;
  return false;
}

HalfwaySystem::HalfwaySystem(const HalfwayParams& params)
    : params_(params), centres_(measuredEntries()), others_(unmeasuredEntries()) {
  std::string error;
  if (!params.isValid(&error)) throw ReconArgumentError("halfway method: " + error);
  std::vector<HalfwayAngles> centreAngles;
  for (const TableEntry& e : centres_) {
    centreAngles.push_back(halfwayAngles(e, params.isotropic));
    centreScale_.push_back(static_cast<float>(foreshortening(e, params.foreshorteningExponent)));
  }
  const int k = std::min<int>(params.neighbours, static_cast<int>(centres_.size()));
  std::vector<std::pair<double, int>> distances(centres_.size());
  for (const TableEntry& e : others_) {
    const HalfwayAngles a = halfwayAngles(e, params.isotropic);
    for (std::size_t c = 0; c < centres_.size(); ++c) {
      const HalfwayAngles& b = centreAngles[c];
      const double dx = a.half.x - b.half.x, dy = a.half.y - b.half.y, dz = a.half.z - b.half.z;
      const double dd = params.differenceWeight * (a.differenceRad - b.differenceRad);
      distances[c] = {dx * dx + dy * dy + dz * dz + dd * dd, static_cast<int>(c)};
    }
    std::partial_sort(distances.begin(), distances.begin() + k, distances.end());
    // Inverse squared distance, softened by the nearest one so that ties share evenly.
    const double soften = distances[0].first + 1e-6;
    double sum = 0.0;
    for (int j = 0; j < k; ++j)
      sum += 1.0 / (distances[j].first + soften);
    for (int j = 0; j < k; ++j) {
      taps_.push_back(
          {distances[j].second, static_cast<float>(1.0 / (distances[j].first + soften) / sum)});
    }
    otherScale_.push_back(
        static_cast<float>(1.0 / foreshortening(e, params.foreshorteningExponent)));
  }
}

Abrdf HalfwaySystem::interpolate(const std::vector<Subspace>& measured) const {
  if (measured.size() != kMeasuredPairs.size()) {
    throw ReconArgumentError("halfway method needs the " +
                             std::to_string(kMeasuredPairs.size()) + " measured subspaces");
  }
  Abrdf table;
  std::vector<Rgb> values;
  values.reserve(centres_.size());
  for (std::size_t s = 0; s < measured.size(); ++s) {
    const Subspace& subspace = measured[s];
    if (subspace.elevations() != kMeasuredPairs[s])
      throw ReconArgumentError("halfway method: subspaces out of the measured-pair order");
    for (int p = 0; p < subspace.lightRing().count; ++p) {
      for (int q = 0; q < subspace.viewRing().count; ++q)
        values.push_back(subspace.at(p, q));
    }
    subspace.writeTo(table);
  }
  Rgb floor;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> channel;
    channel.reserve(values.size());
    for (const Rgb& v : values)
      channel.push_back(v[c]);
    floor[c] = diffuseFloor(std::move(channel));
  }
  const int k = std::min<int>(params_.neighbours, static_cast<int>(centres_.size()));
  for (std::size_t j = 0; j < others_.size(); ++j) {
    Rgb sum{0.0, 0.0, 0.0};
    for (int t = 0; t < k; ++t) {
      const Tap& tap = taps_[j * k + t];
      for (int c = 0; c < 3; ++c) {
        sum[c] += tap.weight *
                  toInterpolatedValue((values[tap.centre][c] - floor[c]) * centreScale_[tap.centre],
                                      params_.valueGamma);
      }
    }
    for (int c = 0; c < 3; ++c) {
      table.channel(others_[j].light, others_[j].view, c) = static_cast<float>(
          floor[c] + fromInterpolatedValue(sum[c], params_.valueGamma) * otherScale_[j]);
    }
  }
  for (float& v : table.values())
    v = std::max(v, 0.0f);
  return table;
}

const HalfwaySystem& sharedHalfwaySystem(const HalfwayParams& params) {
  static std::mutex mutex;
  static std::map<std::tuple<bool, int, double, double, double>, std::unique_ptr<HalfwaySystem>>
      systems;
  const std::lock_guard lock(mutex);
  auto& slot = systems[{params.isotropic, params.neighbours, params.differenceWeight,
                        params.foreshorteningExponent, params.valueGamma}];
  if (!slot) slot = std::make_unique<HalfwaySystem>(params);
  return *slot;
}

std::optional<double> axialVariation(const SliceSet& slices) {
  std::optional<double> worst;
  for (const Slice& slice : slices.slices()) {
    if (slice.id.kind != SliceKind::Axial || slice.samples.empty()) continue;
    double sum = 0.0, sumOfSquares = 0.0;
    for (const SliceSample& sample : slice.samples) {
      const double grey = (sample.value[0] + sample.value[1] + sample.value[2]) / 3.0;
      sum += grey;
      sumOfSquares += grey * grey;
    }
    const double count = static_cast<double>(slice.samples.size());
    const double mean = sum / count;
    if (!(mean > 0.0)) continue;
    const double variance = std::max(0.0, sumOfSquares / count - mean * mean);
    worst = std::max(worst.value_or(0.0), std::sqrt(variance) / mean);
  }
  return worst;
}

Abrdf reconstructHalfway(const SliceSet& slices, const HalfwayParams& params,
                         HalfwayReport* report) {
  std::string error;
  if (!params.isValid(&error)) throw ReconArgumentError("halfway method: " + error);
  HalfwayReport local;
  HalfwayReport& out = report ? *report : local;
  out = {};
  out.axialVariation = axialVariation(slices);
  out.treatedIsotropic =
      params.isotropic || (out.axialVariation && *out.axialVariation < params.isotropyThreshold);
  const std::vector<Subspace> measured = reconstructMeasuredSubspaces(
      slices, out.treatedIsotropic, params.torusRule, "halfway method");
  HalfwayParams systemParams = params;
  systemParams.isotropic = out.treatedIsotropic;
  Abrdf table = sharedHalfwaySystem(systemParams).interpolate(measured);
  if (!out.treatedIsotropic) return table;

  MethodBParams methodB;
  methodB.isotropic = true;
  methodB.torusRule = params.torusRule;
  const Abrdf blended = reconstructMethodB(slices, methodB, &out.methodB);
  for (int l = 0; l < bonn::kDirectionCount; ++l) {
    const double thetaIDeg = bonn::direction(l).thetaDeg;
    for (int v = 0; v < bonn::kDirectionCount; ++v) {
      const double thetaVDeg = bonn::direction(v).thetaDeg;
      const bool interpolatedByB = thetaIDeg >= 30.0 && thetaVDeg >= 30.0;
      const bool bothAt15 = thetaIDeg == 15.0 && thetaVDeg == 15.0;
      if (interpolatedByB || bothAt15) table.set(l, v, blended.at(l, v));
    }
  }
  return table;
}

}  // namespace slicecap::recon
