// What the fitted prior misses at the measured pairs, as a field over the whole table.
#pragma once

#include <Eigen/Core>
#include <map>
#include <vector>

#include "slicecap/core/rgb.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/recon/periodic_signal.hpp"

namespace slicecap::prior {

/// \brief Per slice: its samples' residuals (log domain) at their slice parameters.
using SliceResiduals = std::map<SliceId, std::vector<recon::SignalPoint>>;

/// \brief Adds the residual of every grid entry to `logTable` (kFeatureCount x 3, [light * 81 +
/// view][channel], the log table the residuals were taken against). At a measured pair it is the
/// slice sum of its residual slices, additive in the log domain: axial(u*) + diagonal(w*) minus
/// their value where the two slices cross (docs/method.md §3.2 coordinates), so the samples are kept and
/// the azimuthal structure they show stays. At other pairs it is carried as Method B carries
/// subspaces: along the view elevation first, then along the light elevation, resampled along the
/// varying azimuth, linear in elevation between measured ones and held beyond them. Entries of
/// pairs no residual reaches are left as they are. Throws PriorError when `logTable`
/// is not kFeatureCount x 3.
void addResidualField(const SliceResiduals& residuals, Eigen::Ref<Eigen::MatrixXf> logTable);

}  // namespace slicecap::prior
