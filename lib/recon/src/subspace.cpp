// Subspace blocks: extraction from and insertion into the table, ring resampling and blending.
#include "slicecap/recon/subspace.hpp"

#include <cmath>
#include <stdexcept>

#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {

Subspace::Subspace(ElevationPair elevations)
    : elevations_(elevations),
      lightRing_(&bonn::ringAt(elevations.thetaIDeg)),
      viewRing_(&bonn::ringAt(elevations.thetaVDeg)),
      values_(std::size_t(lightRing_->count) * viewRing_->count) {}

Subspace Subspace::fromTable(const Abrdf& table, ElevationPair elevations) {
  Subspace s(elevations);
  for (int p = 0; p < s.lightRing_->count; ++p) {
    for (int q = 0; q < s.viewRing_->count; ++q) {
      s.at(p, q) = table.at(s.lightRing_->index(p), s.viewRing_->index(q));
    }
  }
  return s;
}

void Subspace::writeTo(Abrdf& table) const {
  for (int p = 0; p < lightRing_->count; ++p) {
    for (int q = 0; q < viewRing_->count; ++q) {
      table.set(lightRing_->index(p), viewRing_->index(q), at(p, q));
    }
  }
}

namespace {

// Where target azimuth k of ring `to` falls on a ring of `fromCount` azimuths: two neighbours and
// the weight of the second. To a ring of one the caller averages instead.
struct RingTap {
  int lower, upper;
  double weight;
};

std::vector<RingTap> ringTaps(int fromCount, const Ring& to) {
  std::vector<RingTap> taps(to.count);
  const double fromStepDeg = 360.0 / fromCount;
  for (int k = 0; k < to.count; ++k) {
    const double position = to.azimuthDeg(k) / fromStepDeg;
    const int j = static_cast<int>(std::floor(position));
    taps[k] = {j % fromCount, (j + 1) % fromCount, position - j};
  }
  return taps;
}

// The value at target azimuth k of a ring of `targetCount` resampled from a ring of `fromCount`
// values value(0..fromCount-1): the two neighbours' lerp, or the mean to the pole.
template <typename Get>
Rgb resampledValue(int fromCount, int targetCount, const std::vector<RingTap>& taps, int k,
                   Get value) {
  if (targetCount == 1) {
    Rgb sum;
    for (int j = 0; j < fromCount; ++j)
      sum += value(j);
    return sum * (1.0 / fromCount);
  }
  return lerp(value(taps[k].lower), value(taps[k].upper), taps[k].weight);
}

// Resamples the values value(0..fromCount-1) of one ring onto `to`, writing out(k).
template <typename Get, typename Put>
void resampleInto(int fromCount, const Ring& to, const std::vector<RingTap>& taps, Get value,
                  Put out) {
  for (int k = 0; k < to.count; ++k)
    out(k, resampledValue(fromCount, to.count, taps, k, value));
}

// blend(low resampled to `target`, high resampled to `target`, t) in one pass, without the two
// resampled blocks; along phi_v (`AlongView`) or phi_i. The same operations in the same order as
// the two steps, so the result is the same bit for bit.
template <bool AlongView>
Subspace resampledBlend(const Subspace& low, const Subspace& high, double t, ElevationPair target) {
  Subspace out(target);
  auto ringOf = [](const Subspace& s) -> const Ring& {
    return AlongView ? s.viewRing() : s.lightRing();
  };
  const Ring& to = ringOf(out);
  const int lowCount = ringOf(low).count;
  const int highCount = ringOf(high).count;
  const std::vector<RingTap> lowTaps = ringTaps(lowCount, to);
  const std::vector<RingTap> highTaps = ringTaps(highCount, to);
  for (int p = 0; p < out.lightRing().count; ++p) {
    for (int q = 0; q < out.viewRing().count; ++q) {
      auto reader = [&](const Subspace& s) {
        return [&s, p, q](int j) { return AlongView ? s.at(p, j) : s.at(j, q); };
      };
      const int k = AlongView ? q : p;
      out.at(p, q) = lerp(resampledValue(lowCount, to.count, lowTaps, k, reader(low)),
                          resampledValue(highCount, to.count, highTaps, k, reader(high)), t);
    }
  }
  return out;
}

}  // namespace

std::vector<Rgb> resampleRing(const std::vector<Rgb>& values, const Ring& to) {
  const int from = static_cast<int>(values.size());
  if (from == 0) throw ReconArgumentError("resampleRing: empty ring");
  std::vector<Rgb> out(to.count);
  resampleInto(
      from, to, ringTaps(from, to), [&](int j) { return values[j]; },
      [&](int k, const Rgb& v) { out[k] = v; });
  return out;
}

Subspace Subspace::resampledToViewElevation(int thetaVDeg) const {
  Subspace out({elevations_.thetaIDeg, thetaVDeg});
  const std::vector<RingTap> taps = ringTaps(viewRing_->count, *out.viewRing_);
  for (int p = 0; p < lightRing_->count; ++p) {
    resampleInto(
        viewRing_->count, *out.viewRing_, taps, [&](int q) { return at(p, q); },
        [&](int q, const Rgb& v) { out.at(p, q) = v; });
  }
  return out;
}

Subspace Subspace::resampledToLightElevation(int thetaIDeg) const {
  Subspace out({thetaIDeg, elevations_.thetaVDeg});
  const std::vector<RingTap> taps = ringTaps(lightRing_->count, *out.lightRing_);
  for (int q = 0; q < viewRing_->count; ++q) {
    resampleInto(
        lightRing_->count, *out.lightRing_, taps, [&](int p) { return at(p, q); },
        [&](int p, const Rgb& v) { out.at(p, q) = v; });
  }
  return out;
}

Subspace Subspace::blendAtViewElevation(const Subspace& low, const Subspace& high, double t,
                                        int thetaVDeg) {
  if (low.elevations_.thetaIDeg != high.elevations_.thetaIDeg) {
    throw ReconArgumentError("Subspace::blendAtViewElevation: blocks of different lights");
  }
  return resampledBlend<true>(low, high, t, {low.elevations_.thetaIDeg, thetaVDeg});
}

Subspace Subspace::blendAtLightElevation(const Subspace& low, const Subspace& high, double t,
                                         int thetaIDeg) {
  if (low.elevations_.thetaVDeg != high.elevations_.thetaVDeg) {
    throw ReconArgumentError("Subspace::blendAtLightElevation: blocks of different views");
  }
  return resampledBlend<false>(low, high, t, {thetaIDeg, low.elevations_.thetaVDeg});
}

Subspace& Subspace::scale(double factor) {
  for (Rgb& v : values_)
    v *= factor;
  return *this;
}

Subspace Subspace::blend(const Subspace& a, const Subspace& b, double t) {
  if (a.elevations_ != b.elevations_) {
    throw ReconArgumentError("Subspace::blend: blocks of different elevations");
  }
  Subspace out(a.elevations_);
  for (std::size_t i = 0; i < out.values_.size(); ++i)
    out.values_[i] = lerp(a.values_[i], b.values_[i], t);
  return out;
}

}  // namespace slicecap::recon
