// Training of the prior: PCA of log-mapped tables through the (small) Gram matrix of the set.
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

#include "slicecap/core/grid.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::prior {

bool TrainingParams::isValid(std::string* error) const {
  if (components < 1 || components > 256) {
    if (error) *error = "components must be 1 to 256";
    return false;
  }
  if (!(floorFraction > 0.0 && floorFraction < 1.0)) {
    if (error) *error = "floor fraction must lie in (0, 1)";
    return false;
  }
  return true;
}

std::vector<double> channelFeatures(const Abrdf& table, int channel, double floorFraction) {
  const auto& cosTheta = bonn::cosines();
  std::vector<double> weighted(kFeatureCount);
  double largest = 0.0;
  for (int l = 0; l < Abrdf::kDirections; ++l) {
    for (int v = 0; v < Abrdf::kDirections; ++v) {
      const double x =
          std::max(0.0, double(table.channel(l, v, channel))) * cosTheta[l] * cosTheta[v];
      weighted[l * Abrdf::kDirections + v] = x;
      largest = std::max(largest, x);
    }
  }
  if (!(largest > 0.0)) throw PriorError("channel has no positive value");
  const double floor = floorFraction * largest;
  for (double& x : weighted)
    x = std::log(x + floor);
  return weighted;
}

PriorModel trainPriorModel(std::span<const Abrdf> tables, const TrainingParams& params,
                           const std::string& provenance) {
  std::string error;
  if (!params.isValid(&error)) throw PriorError("prior training: " + error);
  const int rows = static_cast<int>(tables.size()) * 3;
  if (rows < params.components + 1) {
    throw PriorError("prior training: " + std::to_string(tables.size()) + " tables give " +
                     std::to_string(rows) + " channel vectors, too few for " +
                     std::to_string(params.components) + " components");
  }
  Eigen::MatrixXd x(rows, kFeatureCount);
  for (std::size_t t = 0; t < tables.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      std::vector<double> f;
      try {
        f = channelFeatures(tables[t], c, params.floorFraction);
      } catch (const PriorError& e) {
        throw PriorError("prior training: table " + std::to_string(t) + ", channel " +
                         std::to_string(c) + ": " + e.what());
      }
      x.row(int(t) * 3 + c) = Eigen::Map<const Eigen::RowVectorXd>(f.data(), kFeatureCount);
    }
  }
  const Eigen::RowVectorXd mean = x.colwise().mean();
  x.rowwise() -= mean;
  // The Gram matrix is rows x rows (a few hundred) where the covariance would be 6561^2.
  const Eigen::MatrixXd gram = x * x.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram);
  const Eigen::VectorXd eigenvalues = solver.eigenvalues();  // ascending
  PriorModel model;
  model.floorFraction = params.floorFraction;
  model.provenance = provenance;
  model.mean.assign(mean.data(), mean.data() + kFeatureCount);
  double leftOut = 0.0;
  for (int i = 0; i < rows - params.components; ++i)
    leftOut += std::max(0.0, eigenvalues[i]);
  model.residualVariance = leftOut / rows / kFeatureCount;
  for (int k = 0; k < params.components; ++k) {
    const int i = rows - 1 - k;
    Eigen::VectorXd direction = x.transpose() * solver.eigenvectors().col(i);
    direction.normalize();
    model.variance.push_back(static_cast<float>(std::max(eigenvalues[i], 0.0) / rows));
    for (int j = 0; j < kFeatureCount; ++j)
      model.basis.push_back(static_cast<float>(direction[j]));
  }
  if (!(model.residualVariance > 0.0)) model.residualVariance = 1e-12;
  return model;
}

}  // namespace slicecap::prior
