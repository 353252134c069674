// The texture fit: rows of texels on a few threads, each texel warm-started from its neighbour and
// given the multi-start fit only when the warm start ends poorly (docs/material-fit.md).
#include "slicecap/fit/texture_fit.hpp"

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "parameter_conversion.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/fit/argument_error.hpp"
#include "slicecap/fit/material_fit.hpp"
#include "texel_data.hpp"
#include "tilted_solver.hpp"

namespace slicecap::fit {
namespace {

using detail::FitParameters;
using detail::TiltedParameters;

// A texel's solution, and what it hands to the next one as its warm start.
struct WarmStart {
  TiltedParameters parameters;
  double rmseLevels = 0.0;
};

constexpr std::array<double, detail::kTiltParameters> kFlat{0.0, 0.0};

std::string texelName(int x, int y) {
  return "texel (" + std::to_string(x) + "," + std::to_string(y) + ")";
}

class TextureFitter {
 public:
  TextureFitter(int resolution, const TexelRowReader& readRow, const TextureFitOptions& options)
      : resolution_(resolution), readRow_(readRow), options_(options),
        pairs_(detail::strideGeometry(options.pairStride)),
        firstOfRow_(static_cast<std::size_t>(resolution)),
        firstDone_(static_cast<std::size_t>(resolution), false) {
    result_.resolution = resolution;
    result_.texels.resize(std::size_t(resolution) * std::size_t(resolution));
  }

  TextureFitResult run() {
    const auto started = std::chrono::steady_clock::now();
    const int threads = std::min(options_.threads, resolution_);
    std::vector<std::thread> pool;
    std::exception_ptr failure;
    std::mutex failureMutex;
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&] {
        try {
          for (int row = nextRow_++; row < resolution_ && !abort_; row = nextRow_++) fitRow(row);
        } catch (...) {
          std::lock_guard lock(failureMutex);
          if (!failure) failure = std::current_exception();
          abort_ = true;
          markAllFirstsDone();
        }
      });
    for (std::thread& thread : pool) thread.join();
    if (failure) std::rethrow_exception(failure);
    for (const TexelFit& texel : result_.texels) {
      result_.fitted += texel.status == TexelStatus::Fitted ? 1 : 0;
      result_.multiStart += texel.multiStart ? 1 : 0;
      result_.tiltFitted +=
          texel.status == TexelStatus::Fitted && texel.tilt == TiltStatus::Fitted ? 1 : 0;
    }
    result_.threads = threads;
    result_.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return std::move(result_);
  }

 private:
  void markAllFirstsDone() {
    std::lock_guard lock(firstMutex_);
    std::fill(firstDone_.begin(), firstDone_.end(), true);
    firstCondition_.notify_all();
  }

  // Texel (0, row) starts from texel (0, row - 1): wait for it (its row was taken earlier, and its
  // first texel is the first thing fitted there, so the wait is one texel's fit at most).
  std::optional<WarmStart> startOfRow(int row) {
    if (row == 0) return std::nullopt;
    std::unique_lock lock(firstMutex_);
    firstCondition_.wait(lock, [&] { return firstDone_[std::size_t(row - 1)]; });
    return firstOfRow_[std::size_t(row - 1)];
  }

  void fitRow(int row) {
    std::vector<Abrdf> tables;
    readRow_(row, tables);
    if (tables.size() != std::size_t(resolution_))
      throw FitArgumentError("fitTexture: row " + std::to_string(row) + " has " +
                             std::to_string(tables.size()) + " texels, not " +
                             std::to_string(resolution_));
    std::optional<WarmStart> warm = startOfRow(row);
    for (int x = 0; x < resolution_ && !abort_; ++x) {
      TexelFit& out = result_.texels[std::size_t(row) * std::size_t(resolution_) + std::size_t(x)];
      std::optional<WarmStart> next = fitTexel(tables[std::size_t(x)], x, row, warm, out);
      if (next) warm = next;  // a failed texel hands on the last good solution
      if (x == 0) {
        std::lock_guard lock(firstMutex_);
        firstOfRow_[std::size_t(row)] = warm;
        firstDone_[std::size_t(row)] = true;
        firstCondition_.notify_all();
      }
    }
  }

  std::optional<WarmStart> fitTexel(const Abrdf& table, int x, int y,
                                    const std::optional<WarmStart>& warm, TexelFit& out) const;
  std::optional<WarmStart> solve(const detail::FitData& data, const TiltedParameters& start,
                                 double trustRegionRadius) const;
  TiltStatus settleTilt(const detail::FitData& data, WarmStart& solution) const;
  WarmStart fitted(const detail::FitData& data, WarmStart solution, bool multiStart,
                   TexelFit& out) const;

  int resolution_;
  const TexelRowReader& readRow_;
  TextureFitOptions options_;
  std::vector<detail::TexelPair> pairs_;
  std::atomic<int> nextRow_{0};
  std::atomic<bool> abort_{false};
  std::vector<std::optional<WarmStart>> firstOfRow_;
  std::vector<bool> firstDone_;
  std::mutex firstMutex_;
  std::condition_variable firstCondition_;
  TextureFitResult result_;
};

// One solve from `start`: with the tilt, or flat (tilt zero) when the tilt is not fitted.
std::optional<WarmStart> TextureFitter::solve(const detail::FitData& data,
                                              const TiltedParameters& start,
                                              double trustRegionRadius) const {
  const double residuals = data.residualCount();
  if (options_.fitTilt) {
    const detail::TiltedOutcome solved = detail::solveTiltedFromStart(
        data, start, options_.maxIterations, options_.functionTolerance, trustRegionRadius);
    if (!solved.converged) return std::nullopt;
    return WarmStart{solved.parameters, std::sqrt(2.0 * solved.cost / residuals)};
  }
  const detail::SolveOutcome solved =
      detail::solveFromStart(data, detail::withoutTilt(start), options_.maxIterations,
                             options_.functionTolerance, trustRegionRadius);
  if (!solved.converged) return std::nullopt;
  return WarmStart{detail::withTilt(solved.parameters, kFlat),
                   std::sqrt(2.0 * solved.cost / residuals)};
}

// A lobe too weak to locate leaves the tilt to the diffuse cosine alone, which trades it against
// the albedo: such a texel is refitted flat and says so (docs/material-fit.md "The normal map").
TiltStatus TextureFitter::settleTilt(const detail::FitData& data, WarmStart& solution) const {
  if (!options_.fitTilt) return TiltStatus::Off;
  if (detail::lobeLocatesTilt(solution.parameters.ggx)) return TiltStatus::Fitted;
  solution.parameters.tilt = kFlat;
  const detail::SolveOutcome flat =
      detail::solveFromStart(data, detail::withoutTilt(solution.parameters), options_.maxIterations,
                             options_.functionTolerance, options_.warmTrustRegionRadius);
  if (flat.converged)
    solution = {detail::withTilt(flat.parameters, kFlat),
                std::sqrt(2.0 * flat.cost / data.residualCount())};
  else
    solution.rmseLevels = detail::tiltedRmseLevels(data, solution.parameters);
  return TiltStatus::NoLobe;
}

// The next texel starts from the tilted solution even when this one is reported flat: a matte
// texel's flat refit matches a tilted diffuse poorly, and its residual would let a poor warm start
// of the next texel pass as good (docs/material-fit.md "The normal map").
WarmStart TextureFitter::fitted(const detail::FitData& data, WarmStart solution, bool multiStart,
                                TexelFit& out) const {
  const WarmStart handedOn = solution;
  const TiltStatus tilt = settleTilt(data, solution);
  solution.parameters = detail::canonicalTilted(solution.parameters);
  out = {TexelStatus::Fitted,
         detail::materialOf(detail::withoutTilt(solution.parameters)),
         solution.rmseLevels,
         multiStart,
         "",
         detail::shadingNormalOf(solution.parameters.tilt),
         tilt};
  return handedOn;
}

std::optional<WarmStart> TextureFitter::fitTexel(const Abrdf& table, int x, int y,
                                                 const std::optional<WarmStart>& warm,
                                                 TexelFit& out) const {
  const std::string name = texelName(x, y);
  if (const std::optional<std::string> problem = detail::texelProblem(table)) {
    out.status = *problem == detail::kNoSamples ? TexelStatus::NoSamples : TexelStatus::NotABrdf;
    out.problem = name + ": " + *problem;
    return std::nullopt;
  }
  const detail::FitData data = detail::texelFitData(table, pairs_);
  std::optional<WarmStart> best;
  if (warm) {
    best = solve(data, warm->parameters, options_.warmTrustRegionRadius);
    const double acceptable =
        std::max(options_.warmAcceptFactor * warm->rmseLevels, options_.warmAcceptFloorLevels);
    if (best && best->rmseLevels <= acceptable) return fitted(data, *best, false, out);
  }
  try {
    FitOptions multi;
    multi.trySheen = false;
    multi.tryCoat = false;  // no coat maps: a texel's fit is one GGX lobe on its base
    // The tilted solve below frees the lobe again, so a round start would only cost a solve;
    // whether a texel's anisotropy earns its parameters is not decided in texture mode yet.
    multi.tryIsotropic = false;
    multi.maxIterations = options_.maxIterations;
    const FitResult flat = fitMaterial(table, name, multi);
    // The multi-start fit is flat: the tilt (the neighbour's, if any) is refined from it.
    const TiltedParameters start = detail::withTilt(detail::ggxParametersOf(flat.material),
                                                    warm ? warm->parameters.tilt : kFlat);
    std::optional<WarmStart> refined = solve(data, start, options_.warmTrustRegionRadius);
    if (!refined) refined = WarmStart{start, detail::tiltedRmseLevels(data, start)};
    if (!best || refined->rmseLevels < best->rmseLevels) best = refined;
  } catch (const FitError& e) {
    if (!best) {
      out.status = TexelStatus::NotConverged;
      out.problem = e.what();
      out.multiStart = true;
      return std::nullopt;
    }
  }
  return fitted(data, *best, true, out);
}

}  // namespace

std::string_view toString(TiltStatus status) {
  switch (status) {
    case TiltStatus::Fitted:
      return "fitted";
    case TiltStatus::NoLobe:
      return "flat: no specular lobe to tilt";
    case TiltStatus::Off:
      return "flat: tilt fitting off";
  }
  return "?";
}

std::string_view toString(TexelStatus status) {
  switch (status) {
    case TexelStatus::Fitted: return "fitted";
    case TexelStatus::NoSamples: return "no samples";
    case TexelStatus::NotABrdf: return "not a BRDF";
    case TexelStatus::NotConverged: return "not converged";
  }
  return "?";
}

TextureFitResult fitTexture(int resolution, const TexelRowReader& readRow,
                            const TextureFitOptions& options) {
  if (resolution < 1) throw FitArgumentError("fitTexture: resolution must be at least 1");
  if (options.threads < 1 || options.maxIterations < 1 || options.pairStride < 1 ||
      options.pairStride % 3 == 0 || !(options.warmAcceptFactor >= 1.0) ||
      !(options.warmTrustRegionRadius > 0.0))
    throw FitArgumentError(
        "fitTexture: threads, iterations and pair stride must be >= 1 (the stride not a multiple "
        "of 3, which would see a third of the view directions), the accept factor >= 1");
  TextureFitter fitter(resolution, readRow, options);
  return fitter.run();
}

}  // namespace slicecap::fit
