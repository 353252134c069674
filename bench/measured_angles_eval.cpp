// Reconstruction at the measured angles (issue 31, items 3 and 4): how much the prior and Method B
// lose when the samples do not sit where the slice grid puts them. Every capture is the built-in
// anisotropic material's true BRDF at the samples' own directions (no noise), so the figures
// measure the reconstruction alone. Baselines are measured in the same run:
//   azimuth phase: samples at grid positions (k * step) against mid-bin (k * step + step / 2) and
//   uniformly random positions inside their bins (+- step / 2);
//   elevation: nominal elevations against +- jitter (uniform, light and view independently).
// Random positions and jitter are drawn per material and seed; dE is averaged over --seeds seeds
// (seed, seed + 1, ...) before the ratios are taken.
// --isotropic runs the built-in isotropic materials instead: a set apart from the goal's, on which
// choices can be made without tuning on the figures reported.
// Usage: measured_angles_eval [--jitter-deg D] [--seed N] [--seeds COUNT] [--isotropic]
//        [--per-material]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace {

using namespace slicecap;

enum class Phase { Grid, MidBin, Random };

struct CaptureSpec {
  Phase phase = Phase::Grid;
  double elevationJitterDeg = 0.0;
  unsigned seed = 1;
};

// The 8 slices of the default capture (168 samples) at the spec's azimuth phase and elevation
// jitter, valued with the model at each sample's own directions.
SliceSet capture(const models::ReflectanceModel& model, const CaptureSpec& spec) {
  const SliceSet positions = recon::extractSlices(models::tabulate(model));
  std::mt19937 rng(spec.seed);
  std::uniform_real_distribution<double> unit(-0.5, 0.5);
  SliceSet out;
  for (const Slice& slice : positions.slices()) {
    const double stepDeg = 360.0 / double(slice.samples.size());
    for (const SliceSample& nominal : slice.samples) {
      double parameterDeg = sliceParameterDeg(slice.id.kind, nominal);
      if (spec.phase == Phase::MidBin) parameterDeg += 0.5 * stepDeg;
      if (spec.phase == Phase::Random) parameterDeg += unit(rng) * stepDeg;
      const AzimuthPair azimuths = slicePoint(slice.id.kind, parameterDeg);
      SliceSample s;
      s.light = {double(slice.id.elevations.thetaIDeg), azimuths.phiIDeg};
      s.view = {double(slice.id.elevations.thetaVDeg), azimuths.phiVDeg};
      if (spec.elevationJitterDeg > 0.0) {
        s.light.thetaDeg += 2.0 * unit(rng) * spec.elevationJitterDeg;
        s.view.thetaDeg += 2.0 * unit(rng) * spec.elevationJitterDeg;
      }
      s.value = model.evaluate(toUnitVector(s.light), toUnitVector(s.view));
      out.add(slice.id, s);
    }
  }
  return out;
}

struct Result {
  double prior = 0.0;
  double methodB = 0.0;
};

Result reconstructDe(const Abrdf& truth, const SliceSet& slices) {
  return {
      eval::compare(truth, prior::reconstructWithPrior(slices, prior::defaultPriorModel())).deltaE,
      eval::compare(truth, recon::reconstructMethodB(slices)).deltaE};
}

struct Ratios {
  std::vector<double> values;
  double mean() const {
    double s = 0.0;
    for (double v : values)
      s += v;
    return values.empty() ? 0.0 : s / double(values.size());
  }
  double worst() const {
    double w = 0.0;
    for (double v : values)
      w = std::max(w, v);
    return w;
  }
};

}  // namespace

int main(int argc, char** argv) {
  double jitterDeg = 2.0;
  unsigned seed = 31;
  int seedCount = 5;
  bool perMaterial = false;
  bool isotropic = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--jitter-deg" && i + 1 < argc) {
      jitterDeg = std::atof(argv[++i]);
    } else if (arg == "--seed" && i + 1 < argc) {
      seed = unsigned(std::atoi(argv[++i]));
    } else if (arg == "--seeds" && i + 1 < argc) {
      seedCount = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--isotropic") {
      isotropic = true;
    } else if (arg == "--per-material") {
      perMaterial = true;
    } else {
      std::fprintf(stderr,
                   "usage: measured_angles_eval [--jitter-deg D] [--seed N] [--seeds COUNT] "
                   "[--isotropic] [--per-material]\n");
      return 2;
    }
  }
  const auto materials = isotropic ? models::isotropicMaterials() : models::anisotropicMaterials();
  Ratios midPrior, randomPrior, randomB, jitterPrior, jitterB;
  if (perMaterial)
    std::printf("%-20s %28s %28s %28s %22s\n", "material", "prior grid / mid / random",
                "B grid / mid / random", "prior nominal / jitter", "B nominal / jitter");
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const models::ReflectanceModel& model = *materials[m].model;
    const Abrdf truth = models::tabulate(model);
    const Result grid = reconstructDe(truth, capture(model, {Phase::Grid, 0.0, 0}));
    const Result mid = reconstructDe(truth, capture(model, {Phase::MidBin, 0.0, 0}));
    Result random, jitter;
    for (int k = 0; k < seedCount; ++k) {
      const unsigned materialSeed = (seed + unsigned(k)) * 1000u + unsigned(m);
      const Result r = reconstructDe(truth, capture(model, {Phase::Random, 0.0, materialSeed}));
      const Result j = reconstructDe(truth, capture(model, {Phase::Grid, jitterDeg, materialSeed}));
      random.prior += r.prior / seedCount;
      random.methodB += r.methodB / seedCount;
      jitter.prior += j.prior / seedCount;
      jitter.methodB += j.methodB / seedCount;
    }
    // A material every capture reconstructs exactly (a Lambertian) counts as ratio 1.
    auto ratio = [](double test, double baseline) {
      return baseline > 0.0 ? test / baseline : (test > 0.0 ? HUGE_VAL : 1.0);
    };
    midPrior.values.push_back(ratio(mid.prior, grid.prior));
    randomPrior.values.push_back(ratio(random.prior, grid.prior));
    randomB.values.push_back(ratio(random.methodB, grid.methodB));
    jitterPrior.values.push_back(ratio(jitter.prior, grid.prior));
    jitterB.values.push_back(ratio(jitter.methodB, grid.methodB));
    if (perMaterial)
      std::printf("%-20s %8.3f %8.3f %8.3f    %8.3f %8.3f %8.3f    %8.3f %8.3f    %8.3f %8.3f\n",
                  materials[m].name.c_str(), grid.prior, mid.prior, random.prior, grid.methodB,
                  mid.methodB, random.methodB, grid.prior, jitter.prior, grid.methodB,
                  jitter.methodB);
  }
  auto line = [](const char* what, const Ratios& r) {
    std::printf("%-44s mean %.3f  worst %.3f\n", what, r.mean(), r.worst());
  };
  std::printf("dE ratios over %zu built-in %s materials (seeds %u..%u, jitter +-%.1f deg):\n",
              materials.size(), isotropic ? "isotropic" : "anisotropic", seed,
              seed + unsigned(seedCount) - 1, jitterDeg);
  line("prior, mid-bin / grid azimuths", midPrior);
  line("prior, random in bin / grid azimuths", randomPrior);
  line("Method B, random in bin / grid azimuths", randomB);
  line("prior, elevation jitter / nominal", jitterPrior);
  line("Method B, elevation jitter / nominal", jitterB);
  return 0;
}
