// The texture fit: rows of texels on a few threads, each texel warm-started from its neighbour and
// given the multi-start fit only when the warm start ends poorly (docs/material-fit.md).
#include "slicecap/fit/texture_fit.hpp"

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
#include "slicecap/fit/material_fit.hpp"
#include "texel_data.hpp"

namespace slicecap::fit {
namespace {

using detail::FitParameters;

// The solution a texel hands to the next one.
struct WarmStart {
  FitParameters parameters;
  double rmseLevels = 0.0;
};

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
      throw std::runtime_error("fitTexture: row " + std::to_string(row) + " has " +
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
  std::optional<detail::SolveOutcome> best;
  double bestRmse = 0.0;
  if (warm) {
    detail::SolveOutcome solved =
        detail::solveFromStart(data, warm->parameters, options_.maxIterations,
                               options_.functionTolerance, options_.warmTrustRegionRadius);
    if (solved.converged) {
      bestRmse = std::sqrt(2.0 * solved.cost / data.residualCount());
      best = std::move(solved);
      const double acceptable =
          std::max(options_.warmAcceptFactor * warm->rmseLevels, options_.warmAcceptFloorLevels);
      if (bestRmse <= acceptable) {
        out = {TexelStatus::Fitted, detail::materialOf(best->parameters), bestRmse, false, ""};
        return WarmStart{best->parameters, bestRmse};
      }
    }
  }
  out.multiStart = true;
  try {
    FitOptions multi;
    multi.trySheen = false;
    multi.maxIterations = options_.maxIterations;
    const FitResult fitted = fitMaterial(table, name, multi);
    const FitParameters p = detail::ggxParametersOf(fitted.material);
    const double rmse = detail::rmseLevels(data, p);
    if (!best || rmse < bestRmse) {
      out = {TexelStatus::Fitted, fitted.material, rmse, true, ""};
      return WarmStart{p, rmse};
    }
  } catch (const FitError& e) {
    if (!best) {
      out.status = TexelStatus::NotConverged;
      out.problem = e.what();
      return std::nullopt;
    }
  }
  out = {TexelStatus::Fitted, detail::materialOf(best->parameters), bestRmse, true, ""};
  return WarmStart{best->parameters, bestRmse};
}

}  // namespace

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
  if (resolution < 1) throw std::invalid_argument("fitTexture: resolution must be at least 1");
  if (options.threads < 1 || options.maxIterations < 1 || options.pairStride < 1 ||
      options.pairStride % 3 == 0 || !(options.warmAcceptFactor >= 1.0) ||
      !(options.warmTrustRegionRadius > 0.0))
    throw std::invalid_argument(
        "fitTexture: threads, iterations and pair stride must be >= 1 (the stride not a multiple "
        "of 3, which would see a third of the view directions), the accept factor >= 1");
  TextureFitter fitter(resolution, readRow, options);
  return fitter.run();
}

}  // namespace slicecap::fit
