// Azimuth bins: assignment by slice parameter, median values, circular-mean angles.
#include "slicecap/capture/azimuth_bins.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/hdr_merge.hpp"
#include "slicecap/core/angles.hpp"
#include "slicecap/core/median.hpp"

namespace slicecap::capture {
namespace {

double circularMeanDeg(const std::vector<double>& azimuthsDeg) {
  double x = 0.0, y = 0.0;
  for (double a : azimuthsDeg) {
    x += std::cos(degToRad(a));
    y += std::sin(degToRad(a));
  }
  return wrapDeg360(radToDeg(std::atan2(y, x)));
}

// The next AzimuthBins::version() or run(): one counter for every instance, so two bins never
// share one.
std::uint64_t nextVersion() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

}  // namespace

AzimuthBins::AzimuthBins(SliceKind kind, double binWidthDeg)
    : kind_(kind), binWidthDeg_(binWidthDeg), version_(nextVersion()), run_(nextVersion()) {
  const double count = 360.0 / binWidthDeg;
  if (!std::isfinite(count) || count < 1.0 || std::abs(count - std::round(count)) > 1e-9) {
    throw CaptureError("azimuth bin width must divide 360 deg");
  }
  bins_.resize(static_cast<std::size_t>(std::lround(count)));
}

int AzimuthBins::binOf(double parameterDeg) const {
  const int bin =
      static_cast<int>(std::floor(wrapDeg360(parameterDeg + binWidthDeg_ / 2.0) / binWidthDeg_));
  return std::min(bin, binCount() - 1);
}

int AzimuthBins::binOf(const FrameSample& sample) const {
  return binOf(sliceParameterDeg(kind_, {sample.light, sample.view, sample.value}));
}

void AzimuthBins::add(const FrameSample& sample) {
  bins_[binOf(sample)].push_back(sample);
  version_ = nextVersion();
  clippedCache_.reset();
}

void AzimuthBins::clear() {
  for (auto& bin : bins_)
    bin.clear();
  version_ = nextVersion();
  run_ = nextVersion();
  clippedCache_.reset();
}

void AzimuthBins::removeLatest(int bin) {
  std::vector<FrameSample>& samples = bins_.at(static_cast<std::size_t>(bin));
  if (samples.empty()) return;
  samples.pop_back();
  version_ = nextVersion();
  // Frames taken out (a refused run's) leave a different run: what was judged on them is stale.
  run_ = nextVersion();
  clippedCache_.reset();
}

int AzimuthBins::filledCount() const {
  return static_cast<int>(
      std::count_if(bins_.begin(), bins_.end(), [](const auto& b) { return !b.empty(); }));
}

std::vector<bool> AzimuthBins::filled() const {
  std::vector<bool> out;
  for (const auto& bin : bins_)
    out.push_back(!bin.empty());
  return out;
}

std::optional<HdrMerge> AzimuthBins::mergedHdr(std::size_t b) const {
  const std::vector<FrameSample>& bin = bins_[b];
  // Each frame's slice parameter from the bin's centre: where a cell's frames disagree, the one
  // nearest the centre gives it (and whether it clipped there).
  std::vector<double> offCentreDeg;
  for (const FrameSample& s : bin)
    offCentreDeg.push_back(wrapDeg360(sliceParameterDeg(kind_, {s.light, s.view, s.value}) -
                                      double(b) * binWidthDeg_ + 180.0) -
                           180.0);
  return mergeHdrBin(bin, offCentreDeg);
}

std::vector<int> AzimuthBins::clippedBins() const {
  // Kept until the bins change: the daemon asks at every status request, on its frame loop.
  if (clippedCache_) return *clippedCache_;
  std::vector<int> out;
  for (std::size_t b = 0; b < bins_.size(); ++b) {
    if (bins_[b].empty() || !bins_[b].front().hdr) continue;
    const std::optional<HdrMerge> merged = mergedHdr(b);
    if (merged && merged->clippedCells > 0) out.push_back(static_cast<int>(b));
  }
  clippedCache_ = out;
  return out;
}

std::vector<SliceSample> AzimuthBins::combine() const {
  std::vector<SliceSample> out;
  for (int b = 0; b < binCount(); ++b)
    if (std::optional<SliceSample> sample = combineBin(b)) out.push_back(*sample);
  return out;
}

std::optional<SliceSample> AzimuthBins::combineBin(int b) const {
  const auto& bin = bins_[static_cast<std::size_t>(b)];
  if (bin.empty()) return std::nullopt;
  std::vector<double> channel[3], lightPhi, viewPhi;
  double lightTheta = 0.0, viewTheta = 0.0;
  for (const FrameSample& s : bin) {
    for (std::size_t c = 0; c < 3; ++c)
      channel[c].push_back(s.value[c]);
    lightTheta += s.light.thetaDeg;
    viewTheta += s.view.thetaDeg;
    lightPhi.push_back(s.light.phiDeg);
    viewPhi.push_back(s.view.phiDeg);
  }
  const double n = double(bin.size());
  // An HDR sweep's bin merges its exposures per cell (hdr_merge.hpp); one exposure's frames
  // keep the median, robust to a blurred or occluded frame that passed the gate.
  const std::optional<HdrMerge> merged = mergedHdr(static_cast<std::size_t>(b));
  return SliceSample{{lightTheta / n, circularMeanDeg(lightPhi)},
                     {viewTheta / n, circularMeanDeg(viewPhi)},
                     merged ? merged->value
                            : Rgb{median(channel[0]), median(channel[1]), median(channel[2])}};
}

}  // namespace slicecap::capture
