// Texel by texel Method B (or row-batched Method A) on a pool of threads sharing out the rows.
#include "slicecap/btf/btf_reconstruction.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <thread>

#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/measured_subspaces.hpp"
#include "slicecap/recon/method_a.hpp"
#include "slicecap/vision/pose.hpp"

namespace slicecap::btf {
namespace {

// Counts and the first failure, merged from the threads.
struct Tally {
  std::mutex mutex;
  std::size_t failed = 0, closedForm = 0;
  std::string firstFailure;
  void fail(int column, int row, const std::string& why) {
    const std::lock_guard lock(mutex);
    if (failed++ == 0)
      firstFailure = "texel (" + std::to_string(column) + ", " + std::to_string(row) + "): " + why;
  }
};

void methodBRow(const TextureGrid& grid, const std::vector<SliceTexture>& slices,
                const recon::MethodBParams& params, int row, BtfTexture& out, Tally& tally) {
  std::size_t closedForm = 0;
  std::vector<Abrdf> tables(static_cast<std::size_t>(grid.resolution()));
  for (int column = 0; column < grid.resolution(); ++column) {
    try {
      recon::MethodBReport report;
      tables[std::size_t(column)] =
          recon::reconstructMethodB(texelSlices(grid, slices, column, row), params, &report);
      for (const recon::LineFit& fit : report.fits)
        closedForm += fit.usedClosedForm ? 1 : 0;
    } catch (const recon::ReconstructionError& error) {
      tally.fail(column, row, error.what());
    }
  }
  out.setRow(row, tables);
  const std::lock_guard lock(tally.mutex);
  tally.closedForm += closedForm;
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
  if (!params.methodB.fit.isValid(&error)) throw std::invalid_argument("Method B: " + error);
  const auto started = std::chrono::steady_clock::now();
  BtfTexture out(grid.resolution());
  const int threads =
      std::max(1, params.threads > 0 ? params.threads
                                     : static_cast<int>(std::thread::hardware_concurrency()));
  // Built before the threads start: the one factorisation every texel shares.
  const recon::MethodASystem* system =
      params.method == TexelMethod::A ? &recon::sharedMethodASystem() : nullptr;
  Tally tally;
  std::atomic<int> nextRow{0};
  {
    std::vector<std::jthread> pool;
    for (int t = 0; t < threads; ++t) {
      pool.emplace_back([&] {
        for (int row = nextRow++; row < grid.resolution(); row = nextRow++) {
          if (system)
            methodARow(grid, slices, params.methodB, *system, row, out, tally);
          else
            methodBRow(grid, slices, params.methodB, row, out, tally);
        }
      });
    }
  }
  if (report) {
    report->texels = grid.texelCount();
    report->threads = threads;
    report->failedTexels = tally.failed;
    report->firstFailure = tally.firstFailure;
    report->closedFormFits = tally.closedForm;
    report->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  }
  return out;
}

}  // namespace slicecap::btf
