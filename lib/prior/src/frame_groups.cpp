// Generalised least squares for one frame's correlated cells, as a whitening of the rows.
#include "frame_groups.hpp"

#include <algorithm>
#include <cmath>

namespace slicecap::prior {

FrameWhitening frameWhitening(const std::vector<SampleRow>& rows, const Rgb& floor,
                              double ownLogSigma, double commonLogSigma, bool asOneSample) {
  FrameWhitening out;
  const int groups = frameGroupCount(rows);
  out.scale.assign(rows.size(), 1.0);
  out.share.assign(rows.size(), 0.0);
  out.group.assign(rows.size(), -1);
  if (groups == 0) return out;
  const double own = ownLogSigma * ownLogSigma;
  const double rho = commonLogSigma * commonLogSigma / own;
  std::vector<double> weight(rows.size(), 0.0), total(std::size_t(groups), 0.0);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const SampleRow& r = rows[i];
    if (r.frame < 0) continue;
    // The noise of log(weighted + floor), by the delta method, averaged over the channels.
    double logVariance = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double level = r.weighted[c] + floor[c];
      // A channel dark in every row (its floor underflows) says nothing of the noise.
      if (!(level * level > 1e-300)) continue;
      logVariance += r.weightedVariance[c] / (level * level) / 3.0;
    }
    weight[i] = own / (own + logVariance);
    total[std::size_t(r.frame)] += weight[i];
    out.group[i] = r.frame;
  }
  out.gamma.resize(std::size_t(groups));
  for (int g = 0; g < groups; ++g)
    out.gamma[std::size_t(g)] =
        asOneSample ? 0.0 : 1.0 - 1.0 / std::sqrt(1.0 + rho * total[std::size_t(g)]);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (out.group[i] < 0) continue;
    const double groupTotal = total[std::size_t(out.group[i])];
    out.share[i] = groupTotal > 0.0 ? weight[i] / groupTotal : 0.0;
    out.scale[i] = std::sqrt(asOneSample ? out.share[i] : (1.0 + rho) * weight[i]);
  }
  return out;
}

void whiten(const FrameWhitening& whitening, Eigen::Ref<Eigen::MatrixXd> m) {
  if (!whitening.any()) return;
  Eigen::MatrixXd means = Eigen::MatrixXd::Zero(Eigen::Index(whitening.gamma.size()), m.cols());
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    if (const int g = whitening.group[std::size_t(i)]; g >= 0)
      means.row(g) += whitening.share[std::size_t(i)] * m.row(i);
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    const int g = whitening.group[std::size_t(i)];
    if (g < 0) continue;
    m.row(i) = whitening.scale[std::size_t(i)] *
               (m.row(i) - whitening.gamma[std::size_t(g)] * means.row(g));
  }
}

}  // namespace slicecap::prior
