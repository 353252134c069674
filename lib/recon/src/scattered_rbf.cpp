// The uniform baseline's reconstruction: one small RBF system per sample set.
#include "slicecap/recon/scattered_rbf.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "slicecap/recon/argument_error.hpp"
#include "slicecap/recon/errors.hpp"

namespace slicecap::recon {

Abrdf reconstructScattered(const SliceSet& samples, const ScatteredRbfParams& params) {
  std::string error;
  if (!params.rbf.isValid(&error)) throw ReconArgumentError("scattered RBF: " + error);
  if (samples.empty()) throw ReconstructionError("scattered RBF: no samples");
  // Average samples whose features coincide (to 1e-9 rad): a repeated frame is one centre.
  struct Accumulated {
    Rgb sum;
    int count = 0;
  };
  std::map<FeaturePoint, Accumulated> byFeature;
  for (const Slice& slice : samples.slices()) {
    for (const SliceSample& s : slice.samples) {
      for (std::size_t c = 0; c < 3; ++c) {
        if (!std::isfinite(s.value[c]))
          throw ReconstructionError("scattered RBF: non-finite sample in " + toString(slice.id));
      }
      FeaturePoint f = onionFeatures(s.light, s.view, params.frame);
      for (double& x : f)
        x = std::round(x * 1e9) / 1e9;
      Accumulated& a = byFeature[f];
      a.sum += s.value;
      ++a.count;
    }
  }
  std::vector<FeaturePoint> centres;
  Eigen::MatrixXd values(static_cast<Eigen::Index>(byFeature.size()), 3);
  for (const auto& [feature, accumulated] : byFeature) {
    const auto row = static_cast<Eigen::Index>(centres.size());
    for (int c = 0; c < 3; ++c)
      values(row, c) =
          toInterpolatedValue(accumulated.sum[c] / accumulated.count, params.rbf.valueGamma);
    centres.push_back(feature);
  }
  const RbfInterpolant rbf(std::move(centres), params.rbf);
  const Eigen::MatrixXd coefficients = rbf.coefficients(values);
  Abrdf table;
  for (int l = 0; l < bonn::kDirectionCount; ++l) {
    for (int v = 0; v < bonn::kDirectionCount; ++v) {
      const FeaturePoint x = onionFeatures(bonn::direction(l), bonn::direction(v), params.frame);
      for (int c = 0; c < 3; ++c) {
        const double interpolated = rbf.evaluate(coefficients.col(c), x);
        // NaN from a system singular in floating point would be clipped to a silent zero.
        if (!std::isfinite(interpolated))
          throw ReconstructionError(
              "scattered RBF: the interpolant is not finite: the system is "
              "singular in floating point for these RBF options");
        table.channel(l, v, c) =
            static_cast<float>(fromInterpolatedValue(interpolated, params.rbf.valueGamma));
      }
    }
  }
  return table;
}

}  // namespace slicecap::recon
