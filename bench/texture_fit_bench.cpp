// `slicecap fit BTF_DIR` speed (the goal: SVBRDF maps of a 128 x 128 tile in < 60 s on the
// 2 cores here) and accuracy: a simulated 128 x 128 BTF whose texels have known GGX parameters (a
// woven checker of 16-texel cells brushed at 30 and 120 deg, roughness and anisotropy varying
// smoothly across the tile, 2 % noise on every value), held in half floats as `slicecap btf`
// writes it, fitted on 1 and 2 threads. Counters: the recovered per-texel roughness and tangent
// errors, and the dE of the fitted material against the true (noise-free) table on a sample.
// The tilted variant tilts each texel's shading normal smoothly by up to +-15 deg about each axis
// (tabulated by turning light and view into the tilted frame by hand,
// tests/support/tilted_table.hpp) and reports the recovered normal's error; a run with the tilt
// fitting off is the fit as it was before the normal map. Run it directly
// (build/bench/texture_fit_bench), not through scripts/bench, which pins to one core.
#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <thread>

#include "../tests/support/tilted_table.hpp"
#include "slicecap/btf/btf_texture.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/fit/texture_fit.hpp"

namespace {

using namespace slicecap;

// The tile's side: 128 (the goal), 32 for a quick look; set by the benchmark's argument.
int tileSide = 128;
// Whether the texels' shading normals are tilted (normalAt); set by the benchmark's argument.
bool tiltedTile = false;

fit::FittedMaterial truthAt(int x, int y) {
  const bool weft = ((x / 16) + (y / 16)) % 2 == 0;
  fit::FittedMaterial m;
  m.diffuseAlbedo = weft ? Rgb{0.45, 0.12, 0.1} : Rgb{0.1, 0.15, 0.4};
  m.diffuseAlbedo = m.diffuseAlbedo * (0.8 + 0.4 * y / (tileSide - 1.0));
  m.specularF0 = Rgb::gray(weft ? 0.05 : 0.12);
  m.alphaBitangent = 0.05 + 0.25 * x / (tileSide - 1.0);
  m.alphaTangent = m.alphaBitangent * (1.5 + 2.5 * y / (tileSide - 1.0));
  m.tangentDeg = weft ? 30.0 : 120.0;
  return m.canonical();
}

// The true shading normal: tilted by 15 sin(2 pi x / 64) deg about y (toward +x) and
// 15 cos(2 pi y / 48) deg about x (toward +y), smooth across the tile; (0, 0, 1) when not
// tiltedTile.
test::tilt::Vec normalAt(int x, int y) {
  if (!tiltedTile) return {0.0, 0.0, 1.0};
  const double towardX =
      15.0 * std::sin(2.0 * std::numbers::pi * x / 64.0) * std::numbers::pi / 180;
  const double towardY =
      15.0 * std::cos(2.0 * std::numbers::pi * y / 48.0) * std::numbers::pi / 180;
  return test::tilt::unit({std::tan(towardX), std::tan(towardY), 1.0});
}

// A deterministic +-2 % factor per value (a capture's noise; the fit must not need exact tables).
float noise(std::size_t texel, std::size_t value) {
  std::uint64_t h = texel * 0x9E3779B97F4A7C15ull ^ (value + 0x632BE59BD9B4E019ull);
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 29;
  return 1.0f + 0.02f * (static_cast<float>(h % 20001) / 10000.0f - 1.0f);
}

// The simulated tile of side tileSide (made once per side: 16384 tables take a while).
const btf::BtfTexture& simulatedTexture() {
  static std::unique_ptr<btf::BtfTexture> cached;
  static bool cachedTilted = false;
  if (cached && cached->resolution() == tileSide && cachedTilted == tiltedTile) return *cached;
  cachedTilted = tiltedTile;
  cached.reset();
  cached = std::make_unique<btf::BtfTexture>([] {
    btf::BtfTexture t(tileSide);
    std::vector<std::thread> workers;
    for (int w = 0; w < 2; ++w)
      workers.emplace_back([&t, w] {
        for (int y = w; y < tileSide; y += 2) {
          std::vector<Abrdf> row;
          for (int x = 0; x < tileSide; ++x) {
            Abrdf table = tiltedTile ? test::tilt::tabulateTilted(truthAt(x, y), normalAt(x, y))
                                     : fit::tabulate(truthAt(x, y));
            std::span<float> values = table.values();
            for (std::size_t i = 0; i < values.size(); ++i)
              values[i] *= noise(std::size_t(y * tileSide + x), i);
            row.push_back(std::move(table));
          }
          t.setRow(y, row);
        }
      });
    for (std::thread& worker : workers) worker.join();
    return t;
  }());
  return *cached;
}

// As the command reads a row (lib/cli/src/texture_fit_command.cpp).
void readRow(const btf::BtfTexture& texture, int row, std::vector<Abrdf>& tables) {
  tables.assign(std::size_t(tileSide), Abrdf());
  const std::size_t first = std::size_t(row) * tileSide;
  for (int l = 0; l < Abrdf::kDirections; ++l)
    for (int v = 0; v < Abrdf::kDirections; ++v)
      for (int x = 0; x < tileSide; ++x)
        for (int c = 0; c < 3; ++c)
          tables[std::size_t(x)].channel(l, v, c) = texture.value(l, v, first + std::size_t(x), c);
}

// CPU seconds of the whole process (all threads): on a machine shared with other work the wall
// clock shows the load; CPU / threads is what the fit would take on free cores.
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * double(values.size() - 1))];
}

void reportAccuracy(benchmark::State& state, const fit::TextureFitResult& result) {
  std::vector<double> alphaError, tangentError, deltaE, normalError;
  for (int y = 0; y < tileSide; ++y)
    for (int x = 0; x < tileSide; ++x) {
      const fit::TexelFit& t = result.texels[std::size_t(y * tileSide + x)];
      if (t.status != fit::TexelStatus::Fitted) continue;
      const fit::FittedMaterial truth = truthAt(x, y);
      alphaError.push_back(std::max(std::abs(t.material.alphaTangent / truth.alphaTangent - 1.0),
                                    std::abs(t.material.alphaBitangent / truth.alphaBitangent - 1.0)));
      tangentError.push_back(std::abs(fit::tangentDifferenceDeg(t.material.tangentDeg, truth.tangentDeg)));
      normalError.push_back(test::tilt::angleDeg(t.shadingNormal, normalAt(x, y)));
      if (x % 8 == 3 && y % 8 == 5) {  // 256 texels of a 128 tile: a table and a comparison each
        const UnitVector& n = t.shadingNormal;
        deltaE.push_back(eval::compare(test::tilt::tabulateTilted(truth, normalAt(x, y)),
                                       test::tilt::tabulateTilted(t.material, {n.x, n.y, n.z}))
                             .deltaE);
      }
    }
  state.counters["texels_fitted"] = double(result.fitted);
  state.counters["multi_start"] = double(result.multiStart);
  state.counters["alpha_err_median"] = quantile(alphaError, 0.5);
  state.counters["alpha_err_p95"] = quantile(alphaError, 0.95);
  state.counters["tangent_err_deg_median"] = quantile(tangentError, 0.5);
  state.counters["tangent_err_deg_p95"] = quantile(tangentError, 0.95);
  state.counters["normal_err_deg_median"] = quantile(normalError, 0.5);
  state.counters["normal_err_deg_p95"] = quantile(normalError, 0.95);
  state.counters["tilt_fitted"] = double(result.tiltFitted);
  state.counters["dE_median"] = quantile(deltaE, 0.5);
  state.counters["dE_max"] = quantile(deltaE, 1.0);
}

void BM_FitTexture(benchmark::State& state) {
  tileSide = static_cast<int>(state.range(1));
  tiltedTile = state.range(2) != 0;
  const btf::BtfTexture& texture = simulatedTexture();
  fit::TextureFitOptions options;
  options.threads = static_cast<int>(state.range(0));
  options.fitTilt = state.range(3) != 0;
  fit::TextureFitResult result;
  double cpuSeconds = 0.0;
  for (auto _ : state) {
    const double cpuBefore = processCpuSeconds();
    result = fit::fitTexture(
        tileSide, [&](int row, std::vector<Abrdf>& tables) { readRow(texture, row, tables); }, options);
    cpuSeconds = processCpuSeconds() - cpuBefore;
  }
  state.counters["cpu_s_all_threads"] = cpuSeconds;
  state.counters["ms_cpu_per_texel"] = 1000.0 * cpuSeconds / (tileSide * tileSide);
  reportAccuracy(state, result);
}
// {threads, tile side, tilted tile, fit the tilt} (no ArgNames: scripts/arm64-check filters on
// "BM_FitTexture/1/8/"): the goal's 128 x 128 tile on 2 and 1 threads,
// flat and tilted, and flat without the tilt fit (as before the normal map); a 32 x 32 tile, and an
// 8 x 8 one that scripts/arm64-check runs under emulation (the 128 x 128 tiles take an hour there).
BENCHMARK(BM_FitTexture)
    ->Args({2, 128, 0, 1})
    ->Args({2, 128, 1, 1})
    ->Args({2, 128, 0, 0})
    ->Args({1, 128, 0, 1})
    ->Args({2, 32, 0, 1})
    ->Args({2, 32, 1, 1})
    ->Args({2, 32, 0, 0})
    ->Args({1, 8, 0, 1})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
