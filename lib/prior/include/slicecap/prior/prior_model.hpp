// The learned reconstruction prior: a PCA basis of log-mapped measured tables, its file and its
// training.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/error.hpp"

namespace slicecap::prior {

/// \brief A prior file that cannot be read or written, or a training set that cannot give one; the
/// message names the file (and field) or the input.
class PriorError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief Entries of one channel of a table in the prior's feature space: [light][view].
inline constexpr int kFeatureCount = Abrdf::kDirections * Abrdf::kDirections;

/// \brief A low-dimensional Gaussian model of one channel of a measured table in the feature
/// space x = log(f cos(theta_i) cos(theta_v) + floor), floor = floorFraction times the channel's
/// largest cos-weighted value: mean + sum_k c_k basis_k with c_k ~ N(0, variance_k), plus
/// isotropic residual variance per entry (what the components leave out).
struct PriorModel {
  double floorFraction = 0.01;
  double residualVariance = 0.0;  ///< per entry, of the components not kept
  std::vector<float> mean;        ///< kFeatureCount
  std::vector<float> variance;    ///< one per component, decreasing
  std::vector<float> basis;       ///< components x kFeatureCount, orthonormal rows
  std::string provenance;         ///< free text: training tables, command, licence of the data

  int components() const { return static_cast<int>(variance.size()); }
  const float* component(int k) const { return basis.data() + std::size_t(k) * kFeatureCount; }
};

/// \brief Options of the training.
struct TrainingParams {
  int components = 16;
  double floorFraction = 0.01;
  /// \brief Returns false, with a reason, when a field is out of range.
  bool isValid(std::string* error) const;
};

/// \brief PCA of the feature vectors of every channel of every table. Throws PriorError when there
/// are fewer channel vectors than components + 1, or a table has a channel without a positive
/// value.
PriorModel trainPriorModel(std::span<const Abrdf> tables, const TrainingParams& params = {},
                           const std::string& provenance = {});

/// \brief The feature vector (kFeatureCount) of one channel of a table (see PriorModel).
std::vector<double> channelFeatures(const Abrdf& table, int channel, double floorFraction);

/// \brief Writes the model (little-endian binary, format in docs/reference/file-formats.md "Prior file"). Throws PriorError
/// naming the path on failure, which leaves an old file at `path` as it was (written through a
/// temporary).
void writePriorModel(const std::filesystem::path& path, const PriorModel& model);

/// \brief Reads a model; checks magic, version, sizes, finiteness and positive variances. Throws
/// PriorError naming the path and the field that is wrong.
PriorModel readPriorModel(const std::filesystem::path& path);

}  // namespace slicecap::prior
