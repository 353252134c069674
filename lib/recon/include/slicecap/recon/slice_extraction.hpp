// Ideal slices taken from a full table (eq. 1, docs/method.md §2.2-2.3): the simulated acquisition.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::recon {

/// \brief How a table is read between grid azimuths of a ring.
enum class AzimuthLookup {
  Linear,   ///< periodic linear along each ring (docs/method.md §2.3; default)
  Nearest,  ///< the nearest ring azimuth, ties to the lower index
};

/// \brief One grid entry (light index, view index) and its weight in a lookup.
struct GridWeight {
  int light = 0;
  int view = 0;
  double weight = 0.0;
};

/// \brief The grid entries, with non-zero weights summing to 1, that make up the table's value at
/// ring elevations and any azimuths (up to 4; 2 when one azimuth is on its ring). The same weights
/// serve every pixel of a texture. Throws slicecap::CoreError when an elevation is not a ring.
std::vector<GridWeight> lookupWeights(ElevationPair elevations, const AzimuthPair& azimuths,
                                      AzimuthLookup lookup = AzimuthLookup::Linear);

/// \brief The table's value at ring elevations and any azimuths: along each ring the lookup rule
/// applies (at most two grid values per ring, four in all). Throws slicecap::CoreError when an
/// elevation is not a Bonn ring.
Rgb sampleTable(const Abrdf& table, ElevationPair elevations, const AzimuthPair& azimuths,
                AzimuthLookup lookup = AzimuthLookup::Linear);

/// \brief Options of the simulated acquisition.
struct ExtractionParams {
  /// \brief Slice step; unset = 360 / max(n(theta_i), n(theta_v)) per pair (168 samples in all).
  std::optional<double> stepDeg;
  AzimuthLookup lookup = AzimuthLookup::Linear;
  /// \brief Diagonal slices only (the isotropic capture, 84 samples by default).
  bool diagonalOnly = false;
  /// \brief Returns false with a reason when stepDeg does not divide 360 into 2..360 samples.
  bool isValid(std::string* error) const;
};

/// \brief Number of samples of a slice of this pair (docs/method.md §2.2, or 360 / stepDeg).
int samplesPerSlice(ElevationPair pair, const ExtractionParams& params);

/// \brief The 8 (or 4) ideal slices of a table at the measured pairs. Sample k of a slice sits at
/// parameter k * step: axial at (phi_i, phi_v) = (x, x + 15), diagonal at (360 - x, x).
/// Throws ReconArgumentError for invalid params.
SliceSet extractSlices(const Abrdf& table, const ExtractionParams& params = {});

}  // namespace slicecap::recon
