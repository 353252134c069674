// Method A: the material-independent RBF system, its cache, and the per-capture interpolation.
#include "slicecap/recon/method_a.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <tuple>

#include "slicecap/recon/argument_error.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/measured_subspaces.hpp"

namespace slicecap::recon {
namespace {

bool isMeasuredPair(int light, int view) {
  const ElevationPair pair{bonn::kRings[bonn::ringOfIndex(light)].thetaDeg,
                           bonn::kRings[bonn::ringOfIndex(view)].thetaDeg};
  return std::find(kMeasuredPairs.begin(), kMeasuredPairs.end(), pair) != kMeasuredPairs.end();
}

}  // namespace

std::vector<TableEntry> measuredEntries() {
  std::vector<TableEntry> entries;
  for (ElevationPair pair : kMeasuredPairs) {
    const Ring& lightRing = bonn::ringAt(pair.thetaIDeg);
    const Ring& viewRing = bonn::ringAt(pair.thetaVDeg);
    for (int p = 0; p < lightRing.count; ++p) {
      for (int q = 0; q < viewRing.count; ++q)
        entries.push_back({lightRing.index(p), viewRing.index(q)});
    }
  }
  return entries;
}

std::vector<TableEntry> unmeasuredEntries() {
  std::vector<TableEntry> entries;
  for (int l = 0; l < bonn::kDirectionCount; ++l) {
    for (int v = 0; v < bonn::kDirectionCount; ++v) {
      if (!isMeasuredPair(l, v)) entries.push_back({l, v});
    }
  }
  return entries;
}

namespace {

std::vector<FeaturePoint> featuresOf(const std::vector<TableEntry>& entries, OnionFrame frame) {
  std::vector<FeaturePoint> features;
  features.reserve(entries.size());
  for (const TableEntry& e : entries)
    features.push_back(onionFeatures(bonn::direction(e.light), bonn::direction(e.view), frame));
  return features;
}

}  // namespace

MethodASystem::MethodASystem(OnionFrame frame, const RbfParams& rbf)
    : frame_(frame),
      centres_(measuredEntries()),
      others_(unmeasuredEntries()),
      rbf_(featuresOf(centres_, frame), rbf),
      evaluation_(rbf_.evaluationMatrix(featuresOf(others_, frame))) {}

Eigen::MatrixXf MethodASystem::interpolateOthers(const Eigen::MatrixXd& centreValues) const {
  const Eigen::MatrixXf coefficients = rbf_.coefficients(centreValues).cast<float>();
  return evaluation_ * coefficients;
}

Abrdf MethodASystem::interpolate(const std::vector<Subspace>& measured, double valueGamma) const {
  if (measured.size() != kMeasuredPairs.size()) {
    throw ReconArgumentError("Method A needs the " + std::to_string(kMeasuredPairs.size()) +
                             " measured subspaces");
  }
  Abrdf table;
  Eigen::MatrixXd values(static_cast<Eigen::Index>(centres_.size()), 3);
  Eigen::Index row = 0;
  for (std::size_t k = 0; k < measured.size(); ++k) {
    const Subspace& s = measured[k];
    if (s.elevations() != kMeasuredPairs[k])
      throw ReconArgumentError("Method A: subspaces out of the measured-pair order");
    for (int p = 0; p < s.lightRing().count; ++p) {
      for (int q = 0; q < s.viewRing().count; ++q, ++row) {
        for (int c = 0; c < 3; ++c)
          values(row, c) = toInterpolatedValue(s.at(p, q)[c], valueGamma);
      }
    }
    s.writeTo(table);
  }
  const Eigen::MatrixXf others = interpolateOthers(values);
  // A system singular in floating point (the inverse multiquadric with r0 near 0, a multiquadric
  // flat over the centres) gives NaN, which the clipping below would make silent zeros.
  if (!others.allFinite())
    throw ReconstructionError(
        "Method A: the RBF interpolant is not finite: the system is "
        "singular in floating point for these RBF options");
  for (std::size_t j = 0; j < others_.size(); ++j) {
    for (int c = 0; c < 3; ++c) {
      table.channel(others_[j].light, others_[j].view, c) = static_cast<float>(
          fromInterpolatedValue(others(static_cast<Eigen::Index>(j), c), valueGamma));
    }
  }
  for (float& v : table.values())
    v = std::max(v, 0.0f);
  return table;
}

std::size_t MethodASystem::memoryBytes() const {
  return rbf_.memoryBytes() + std::size_t(evaluation_.size()) * sizeof(float);
}

const MethodASystem& sharedMethodASystem(OnionFrame frame, const RbfParams& rbf) {
  std::string error;
  if (!rbf.isValid(&error)) throw ReconArgumentError(error);
  static std::mutex mutex;
  // valueGamma is applied around the system, so systems differing only in it are one.
  using Key = std::tuple<OnionFrame, double, double, RbfKernel, RbfPolynomial>;
  static std::map<Key, std::unique_ptr<MethodASystem>> systems;
  const std::lock_guard lock(mutex);
  auto& slot =
      systems[{frame, rbf.shapeRad.value_or(0.0), rbf.shapeScale, rbf.kernel, rbf.polynomial}];
  if (!slot) slot = std::make_unique<MethodASystem>(frame, rbf);
  return *slot;
}

Abrdf reconstructMethodA(const SliceSet& slices, const MethodAParams& params) {
  std::string error;
  if (!params.isValid(&error)) throw ReconArgumentError("Method A: " + error);
  const std::vector<Subspace> measured =
      reconstructMeasuredSubspaces(slices, params.isotropic, params.torusRule, "Method A");
  return sharedMethodASystem(params.frame, params.rbf).interpolate(measured, params.rbf.valueGamma);
}

}  // namespace slicecap::recon
