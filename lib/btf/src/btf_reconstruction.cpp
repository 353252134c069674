// Texel by texel Method B or the prior (or row-batched Method A) on a pool of threads sharing out
// the rows.
#include "slicecap/btf/btf_reconstruction.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <thread>

#include "slicecap/btf/btf_error.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/measured_subspaces.hpp"
#include "slicecap/recon/method_a.hpp"
#include "slicecap/vision/pose.hpp"

namespace slicecap::btf {
namespace {

// What a row's texels counted, merged into the tally once per row.
struct RowCounts {
  std::size_t closedForm = 0, priorBlended = 0, priorAnisotropic = 0;
};

// Counts and the first failure, merged from the threads.
struct Tally {
  std::mutex mutex;
  std::size_t failed = 0;
  RowCounts counts;
  std::string firstFailure;
  void fail(int column, int row, const std::string& why) {
    const std::lock_guard lock(mutex);
    if (failed++ == 0)
      firstFailure = "texel (" + std::to_string(column) + ", " + std::to_string(row) + "): " + why;
  }
  void add(const RowCounts& row) {
    const std::lock_guard lock(mutex);
    counts.closedForm += row.closedForm;
    counts.priorBlended += row.priorBlended;
    counts.priorAnisotropic += row.priorAnisotropic;
  }
};

// A row of texels one by one: `reconstruct(samples, counts)` gives a texel's table or throws
// recon::ReconstructionError (the texel then stays zero and is counted as failed).
template <typename ReconstructTexel>
void texelByTexelRow(const TextureGrid& grid, const std::vector<SliceTexture>& slices, int row,
                     BtfTexture& out, Tally& tally, ReconstructTexel reconstruct) {
  RowCounts counts;
  std::vector<Abrdf> tables(static_cast<std::size_t>(grid.resolution()));
  for (int column = 0; column < grid.resolution(); ++column) {
    try {
      tables[std::size_t(column)] = reconstruct(texelSlices(grid, slices, column, row), counts);
    } catch (const recon::ReconstructionError& error) {
      tally.fail(column, row, error.what());
    }
  }
  out.setRow(row, tables);
  tally.add(counts);
}

Abrdf methodBTexel(const SliceSet& samples, const recon::MethodBParams& params, RowCounts& counts) {
  recon::MethodBReport report;
  Abrdf table = recon::reconstructMethodB(samples, params, &report);
  for (const recon::LineFit& fit : report.fits)
    counts.closedForm += fit.usedClosedForm ? 1 : 0;
  return table;
}

Abrdf priorTexel(const SliceSet& samples, const prior::PriorReconstructor& reconstructor,
                 RowCounts& counts) {
  prior::PriorReport report;
  Abrdf table = reconstructor.reconstruct(samples, &report);
  counts.priorBlended += report.methodBBlended ? 1 : 0;
  counts.priorAnisotropic += report.anisotropyTermsUsed ? 1 : 0;
  return table;
}

// A row of texels through the shared Method A system as one matrix product.
void methodARow(const TextureGrid& grid, const std::vector<SliceTexture>& slices,
                const recon::MethodBParams& params, const recon::MethodASystem& system, int row,
                BtfTexture& out, Tally& tally) {
  const int n = grid.resolution();
  const auto centres = static_cast<Eigen::Index>(system.centreEntries().size());
  Eigen::MatrixXd values = Eigen::MatrixXd::Zero(centres, 3 * n);
  std::vector<Abrdf> tables(static_cast<std::size_t>(n));
  std::vector<bool> ok(static_cast<std::size_t>(n), false);
  for (int column = 0; column < n; ++column) {
    try {
      const std::vector<recon::Subspace> measured = recon::reconstructMeasuredSubspaces(
          texelSlices(grid, slices, column, row), params.isotropic, params.torusRule, "Method A");
      Eigen::Index k = 0;
      for (const recon::Subspace& s : measured) {
        for (int p = 0; p < s.lightRing().count; ++p)
          for (int q = 0; q < s.viewRing().count; ++q, ++k)
            for (int c = 0; c < 3; ++c)
              values(k, 3 * column + c) = s.at(p, q)[c];
        s.writeTo(tables[std::size_t(column)]);
      }
      ok[std::size_t(column)] = true;
    } catch (const recon::ReconstructionError& error) {
      tally.fail(column, row, error.what());
    }
  }
  const Eigen::MatrixXf others = system.interpolateOthers(values);
  const auto& entries = system.otherEntries();
  for (int column = 0; column < n; ++column) {
    if (!ok[std::size_t(column)]) continue;
    Abrdf& table = tables[std::size_t(column)];
    for (std::size_t j = 0; j < entries.size(); ++j)
      for (int c = 0; c < 3; ++c)
        table.channel(entries[j].light, entries[j].view, c) =
            others(static_cast<Eigen::Index>(j), 3 * column + c);
    for (float& v : table.values())
      v = std::max(v, 0.0f);
  }
  out.setRow(row, tables);
}

}  // namespace

SliceSet texelSlices(const TextureGrid& grid, const std::vector<SliceTexture>& slices, int column,
                     int row) {
  const Eigen::Vector3d point = grid.texelCentreMm(column, row);
  const std::size_t texel = grid.index(column, row);
  SliceSet out;
  for (const SliceTexture& slice : slices) {
    for (const TextureBin& bin : slice.bins) {
      if (bin.frames == 0) continue;
      const float* v = &bin.texels[3 * texel];
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) continue;
      out.add(slice.slice, {vision::directionFrom(point, bin.lightMm),
                            vision::directionFrom(point, bin.cameraMm),
                            {v[0], v[1], v[2]}});
    }
  }
  return out;
}

BtfTexture reconstructBtf(const TextureGrid& grid, const std::vector<SliceTexture>& slices,
                          const BtfReconstructionParams& params, BtfReconstructionReport* report) {
  std::string error;
  if (std::find(kTexelMethods.begin(), kTexelMethods.end(), params.method) == kTexelMethods.end())
    throw BtfError("method " + methods::cliName(params.method) +
                   " does not reconstruct texels (b, a or prior do)");
  if (!params.methodB.fit.isValid(&error)) throw BtfError("Method B: " + error);
  if (params.method == methods::MethodId::Prior) {
    if (!params.priorModel) throw BtfError("the prior method needs a prior model");
    if (!params.prior.isValid(&error)) throw BtfError("prior: " + error);
  }
  const auto started = std::chrono::steady_clock::now();
  BtfTexture out(grid.resolution());
  const int threads =
      std::max(1, params.threads > 0 ? params.threads
                                     : static_cast<int>(std::thread::hardware_concurrency()));
  // Built before the threads start: the one factorisation every texel shares.
  const recon::MethodASystem* system =
      params.method == methods::MethodId::A ? &recon::sharedMethodASystem() : nullptr;
  // The prior's basis entry by entry, shared likewise.
  const std::optional<prior::PriorReconstructor> priorReconstructor =
      params.method == methods::MethodId::Prior ? std::optional<prior::PriorReconstructor>(
                                                std::in_place, *params.priorModel, params.prior)
                                          : std::nullopt;
  Tally tally;
  std::atomic<int> nextRow{0};
  {
    std::vector<std::jthread> pool;
    for (int t = 0; t < threads; ++t) {
      pool.emplace_back([&] {
        for (int row = nextRow++; row < grid.resolution(); row = nextRow++) {
          if (system)
            methodARow(grid, slices, params.methodB, *system, row, out, tally);
          else if (params.method == methods::MethodId::Prior)
            texelByTexelRow(grid, slices, row, out, tally,
                            [&](const SliceSet& samples, RowCounts& counts) {
                              return priorTexel(samples, *priorReconstructor, counts);
                            });
          else
            texelByTexelRow(grid, slices, row, out, tally,
                            [&](const SliceSet& samples, RowCounts& counts) {
                              return methodBTexel(samples, params.methodB, counts);
                            });
        }
      });
    }
  }
  if (report) {
    report->texels = grid.texelCount();
    report->threads = threads;
    report->failedTexels = tally.failed;
    report->firstFailure = tally.firstFailure;
    report->closedFormFits = tally.counts.closedForm;
    report->priorBlendedTexels = tally.counts.priorBlended;
    report->priorAnisotropicTexels = tally.counts.priorAnisotropic;
    report->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }
  return out;
}

}  // namespace slicecap::btf
