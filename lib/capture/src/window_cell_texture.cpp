// Texture in a sweep's window cells (docs/method.md §9.4, "Textured materials").
#include "slicecap/capture/window_cell_texture.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/core/median.hpp"

namespace slicecap::capture {
namespace {

bool usable(const CellSample& cell) {
  return !cell.clipped && std::isfinite(cell.value.mean());
}

// One frame's cells as the measurement reads them: log(cell / the frame's mean of cells) per
// position and channel, that mean, and which channels hold a signal in every cell.
struct FrameRatios {
  std::vector<Rgb> logRatio;
  Rgb mean;
  std::array<bool, 3> measured{};
};

// A frame whose every cell is usable and whose mean is positive in some channel; nullopt for any
// other. A channel counts only where every cell reads minCellSnr sigma above zero: a cell in the
// noise (clamped at 0 when the room light's subtraction overshoots) is no reading of its spot,
// and a single-exposure sweep metered for a metal's peak leaves most frames there.
std::optional<FrameRatios> ratiosOf(const WindowCells& window, std::size_t positions,
                                    double minCellSnr) {
  if (window.cells.size() != positions) return std::nullopt;
  FrameRatios out;
  out.measured = {true, true, true};
  for (const CellSample& cell : window.cells) {
    if (!usable(cell)) return std::nullopt;
    out.mean += cell.value;
    for (std::size_t c = 0; c < 3; ++c)
      if (!(cell.value[c] >= minCellSnr * std::sqrt(cell.variance[c]))) out.measured[c] = false;
  }
  out.mean *= 1.0 / double(positions);
  for (std::size_t c = 0; c < 3; ++c) out.measured[c] = out.measured[c] && out.mean[c] > 0.0;
  if (!(out.measured[0] || out.measured[1] || out.measured[2])) return std::nullopt;
  out.logRatio.resize(positions);
  for (std::size_t k = 0; k < positions; ++k)
    for (std::size_t c = 0; c < 3; ++c)
      // Floored at a thousandth of the mean: a cell read at 0 (a rule with minCellSnr 0) is far
      // below its mean, not infinitely.
      out.logRatio[k][c] =
          out.measured[c]
              ? std::log(std::max(window.cells[k].value[c], 1e-3 * out.mean[c]) / out.mean[c])
              : 0.0;
  return out;
}

// Cells of different positions and frames that saw the same directions (within the pool
// tolerance of sliceFromCells) read the same value if the texture is a factor and the factors
// are divided out; their disagreement with the factors divided out over that as read, x 100. A
// weave's threads, each its own lobe, disagree more once divided (a lobe scaled by the other
// thread's diffuse ratio); a print's spots agree. Linear values, so the bright pairs (a lobe's)
// weigh most, as they do in the table. 100 when no two cells share directions (sparse frames:
// nothing says a factor would do). Sets texture's unexplainedPercent, matchedPairs, binsMatched
// and binsWithCells.
void measureUnexplained(const AzimuthBins& bins, std::size_t positions,
                        const CellTextureRule& rule, CellTexture& texture) {
  const std::vector<Rgb>& factors = texture.albedoFactors;
  struct Seen {
    UnitVector light, view;
    std::size_t position;
    std::uint64_t frame;
    Rgb read, normalised;
  };
  const double tolerance = rule.matchToleranceDeg * std::numbers::pi / 180.0;
  double readSquares = 0.0, normalisedSquares = 0.0;
  for (int b = 0; b < bins.binCount(); ++b) {
    const std::int64_t pairsBefore = texture.matchedPairs;
    std::vector<Seen> seen;
    for (const FrameSample& frame : bins.samplesIn(b)) {
      if (!frame.cells || frame.cells->cells.size() != positions) continue;
      for (std::size_t k = 0; k < positions; ++k) {
        const CellSample& cell = frame.cells->cells[k];
        if (!usable(cell)) continue;
        Rgb normalised;
        for (std::size_t c = 0; c < 3; ++c) normalised[c] = cell.value[c] / factors[k][c];
        seen.push_back({toUnitVector(cell.light), toUnitVector(cell.view), k, frame.frameIndex,
                        cell.value, normalised});
      }
    }
    auto chord2 = [](const UnitVector& u, const UnitVector& w) {
      return (u.x - w.x) * (u.x - w.x) + (u.y - w.y) * (u.y - w.y) + (u.z - w.z) * (u.z - w.z);
    };
    for (std::size_t i = 0; i < seen.size(); ++i)
      for (std::size_t j = i + 1; j < seen.size(); ++j) {
        const Seen &p = seen[i], &q = seen[j];
        if (p.position == q.position || p.frame == q.frame) continue;
        // The chord of a small angle is the angle (radians) to a part in 10^5.
        if (chord2(p.light, q.light) + chord2(p.view, q.view) > tolerance * tolerance) continue;
        for (std::size_t c = 0; c < 3; ++c) {
          readSquares += std::pow(p.read[c] - q.read[c], 2);
          normalisedSquares += std::pow(p.normalised[c] - q.normalised[c], 2);
        }
        ++texture.matchedPairs;
      }
    if (!seen.empty()) ++texture.binsWithCells;
    if (texture.matchedPairs > pairsBefore) ++texture.binsMatched;
  }
  texture.unexplainedPercent =
      readSquares > 0.0 ? 100.0 * std::sqrt(normalisedSquares / readSquares) : 100.0;
}

}  // namespace

std::string_view toString(CellTextureAction action) {
  switch (action) {
    case CellTextureAction::AsRead: return "as read";
    case CellTextureAction::AlbedoNormalised: return "albedo-normalised";
    case CellTextureAction::WindowCentres: return "window centres";
  }
  return "?";
}

std::optional<CellTextureAction> parseCellTextureAction(std::string_view text) {
  if (text == "as-read") return CellTextureAction::AsRead;
  if (text == "normalise") return CellTextureAction::AlbedoNormalised;
  if (text == "centres") return CellTextureAction::WindowCentres;
  return std::nullopt;
}

std::string CellTexture::describe() const {
  char text[200];
  const std::string name(toString(action));
  if (albedoFactors.empty())
    std::snprintf(text, sizeof text, "cells: %s (texture not measured: %d frames)", name.c_str(),
                  framesUsed);
  else if (matchedPairs == 0)
    std::snprintf(text, sizeof text,
                  "cells: %s (texture spread %.0f %%; no two cells of different spots at the same "
                  "directions)",
                  name.c_str(), spreadPercent);
  else
    std::snprintf(text, sizeof text,
                  "cells: %s (texture spread %.0f %%, unexplained %.0f %% over %ld cell pairs in "
                  "%d of %d bins)",
                  name.c_str(), spreadPercent, unexplainedPercent, long(matchedPairs), binsMatched,
                  binsWithCells);
  return text;
}

namespace {

// A threshold of the rule as it is set (10, 5, 50).
std::string rulePercent(double threshold) {
  char text[48];
  std::snprintf(text, sizeof text, "%g", threshold);
  return text;
}

// `value` in as few decimals (none up to 6) as show it on its side of `threshold`: a spread of
// 10.3 is not "10 % over 10 %", an unexplained 5.2 not "5 % left, under 5 % needed".
std::string percentBeside(double value, double threshold) {
  char text[48];
  for (int decimals = 0;; ++decimals) {
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    char other[48];
    std::snprintf(other, sizeof other, "%.*f", decimals, threshold);
    if (value == threshold || std::string(text) != other || decimals == 6) return text;
  }
}

}  // namespace

std::string verdictReason(const CellTexture& texture, const CellTextureRule& rule) {
  const std::string spread = percentBeside(texture.spreadPercent, rule.textureSpreadPercent);
  const std::string threshold = rulePercent(rule.textureSpreadPercent);
  char text[320];
  if (rule.forced)
    std::snprintf(text, sizeof text, "set by the command line, whatever the cells show");
  else if (texture.albedoFactors.empty())
    // The frames a channel was measured in, not framesUsed: a frame counts there when any of
    // its channels is clear of the noise, so it may reach the count while no channel does.
    std::snprintf(text, sizeof text,
                  "texture not measured: %d frames with every cell clear of the noise in a "
                  "channel, %d needed",
                  texture.framesInBestChannel, std::max(rule.minFrames, 1));
  else if (texture.action == CellTextureAction::AsRead)
    std::snprintf(text, sizeof text, "spread %s %%, within the %s %% of a plain material",
                  spread.c_str(), threshold.c_str());
  else if (texture.matchedPairs == 0)
    std::snprintf(text, sizeof text,
                  "texture (spread %s %% over %s %%), and no two cells of different spots at "
                  "the same directions to show a factor explains it",
                  spread.c_str(), threshold.c_str());
  else if (texture.unexplainedPercent >= rule.unexplainedPercent)
    std::snprintf(text, sizeof text,
                  "texture (spread %s %% over %s %%) that the albedo factors do not explain: "
                  "%s %% left, under %s %% needed",
                  spread.c_str(), threshold.c_str(),
                  percentBeside(texture.unexplainedPercent, rule.unexplainedPercent).c_str(),
                  rulePercent(rule.unexplainedPercent).c_str());
  else if (texture.action == CellTextureAction::WindowCentres)
    std::snprintf(text, sizeof text,
                  "texture (spread %s %% over %s %%) whose factors are shown in %d of %d bins "
                  "only, %s %% needed",
                  spread.c_str(), threshold.c_str(), texture.binsMatched, texture.binsWithCells,
                  rulePercent(100.0 * rule.matchedBinsFraction).c_str());
  else
    std::snprintf(text, sizeof text,
                  "texture (spread %s %% over %s %%) that the albedo factors explain: %s %% "
                  "left over %ld cell pairs in %d of %d bins",
                  spread.c_str(), threshold.c_str(),
                  percentBeside(texture.unexplainedPercent, rule.unexplainedPercent).c_str(),
                  long(texture.matchedPairs), texture.binsMatched, texture.binsWithCells);
  return text;
}

nlohmann::json toJson(const CellTexture& texture) {
  return {{"action", std::string(toString(texture.action))},
          {"frames_used", texture.framesUsed},
          {"spread_percent", texture.spreadPercent},
          {"unexplained_percent", texture.unexplainedPercent},
          {"matched_pairs", texture.matchedPairs},
          {"bins_matched", texture.binsMatched},
          {"bins_with_cells", texture.binsWithCells},
          {"summary", texture.describe()}};
}

CellTexture cellTextureOf(const AzimuthBins& bins, const CellTextureRule& rule) {
  std::size_t positions = 0;
  std::vector<FrameRatios> frames;
  for (int b = 0; b < bins.binCount(); ++b)
    for (const FrameSample& frame : bins.samplesIn(b)) {
      if (!frame.cells) continue;
      if (positions == 0) positions = frame.cells->cells.size();
      if (std::optional<FrameRatios> ratios = ratiosOf(*frame.cells, positions, rule.minCellSnr))
        frames.push_back(std::move(*ratios));
    }
  CellTexture out;
  out.framesUsed = int(frames.size());
  // A channel with too few measured frames says nothing: its factors stay 1, out of the spread.
  std::array<std::vector<std::size_t>, 3> framesOf;
  for (std::size_t f = 0; f < frames.size(); ++f)
    for (std::size_t c = 0; c < 3; ++c)
      if (frames[f].measured[c]) framesOf[c].push_back(f);
  const std::size_t enough = std::size_t(std::max(rule.minFrames, 1));
  std::size_t channels = 0;
  for (std::size_t c = 0; c < 3; ++c) {
    channels += framesOf[c].size() >= enough ? 1 : 0;
    out.framesInBestChannel = std::max(out.framesInBestChannel, int(framesOf[c].size()));
  }
  if (channels == 0) {
    if (rule.forced == CellTextureAction::WindowCentres) out.action = *rule.forced;
    return out;
  }
  out.albedoFactors.assign(positions, Rgb::gray(1.0));
  double squares = 0.0;
  std::vector<double> logFactor(positions), scatter2(positions), column;
  for (std::size_t c = 0; c < 3; ++c) {
    if (framesOf[c].size() < enough) continue;
    // Per position the median over the frames, and the square of the scatter that median has
    // from the frames' own scatter alone: (1.2533 sigma)^2 / n, sigma from the median absolute
    // deviation (the median of n normal draws scatters by 1.2533 sigma / sqrt(n)).
    for (std::size_t k = 0; k < positions; ++k) {
      column.clear();
      for (std::size_t f : framesOf[c]) column.push_back(frames[f].logRatio[k][c]);
      logFactor[k] = median(column);
      out.albedoFactors[k][c] = std::exp(logFactor[k]);
      for (double& v : column) v = std::abs(v - logFactor[k]);
      const double sigma = 1.4826 * median(column);
      scatter2[k] = 1.2533 * 1.2533 * sigma * sigma / double(framesOf[c].size());
    }
    // A level common to every position (the median of ratios to a mean that a lobe's few bright
    // cells raise puts every position below 1) is no pattern: the spread is about the mean. The
    // factors keep it, as before: they are ratios to the frame's mean of cells, which a sweep
    // normalised by them reads. Taking each position's scatter off a spread about the mean
    // over-counts the scatter by one mean's worth (1 / positions of it): negligible at 36-64.
    double level = 0.0;
    if (rule.spreadBeyondScatter)
      for (std::size_t k = 0; k < positions; ++k) level += logFactor[k] / double(positions);
    for (std::size_t k = 0; k < positions; ++k)
      squares += std::pow(logFactor[k] - level, 2) - (rule.spreadBeyondScatter ? scatter2[k] : 0.0);
  }
  out.spreadPercent = 100.0 * std::sqrt(std::max(squares, 0.0) / double(channels * positions));
  measureUnexplained(bins, positions, rule, out);
  if (rule.forced)
    out.action = *rule.forced;
  else if (out.spreadPercent <= rule.textureSpreadPercent)
    out.action = CellTextureAction::AsRead;
  else if (out.unexplainedPercent < rule.unexplainedPercent &&
           out.binsMatched >= rule.matchedBinsFraction * out.binsWithCells)
    out.action = CellTextureAction::AlbedoNormalised;
  else
    out.action = CellTextureAction::WindowCentres;
  return out;
}

AzimuthBins withCellsNormalised(const AzimuthBins& bins, const std::vector<Rgb>& factors) {
  AzimuthBins out(bins.kind(), bins.binWidthDeg());
  for (int b = 0; b < bins.binCount(); ++b)
    for (FrameSample frame : bins.samplesIn(b)) {
      if (frame.cells) {
        if (frame.cells->cells.size() != factors.size())
          throw CaptureError("window cells: a frame of " +
                             std::to_string(frame.cells->cells.size()) + " cells for " +
                             std::to_string(factors.size()) + " albedo factors");
        for (std::size_t k = 0; k < factors.size(); ++k)
          for (std::size_t c = 0; c < 3; ++c) {
            frame.cells->cells[k].value[c] /= factors[k][c];
            frame.cells->cells[k].variance[c] /= factors[k][c] * factors[k][c];
          }
      }
      out.add(frame);
    }
  return out;
}

std::optional<AzimuthBins> cellsAsJudged(const AzimuthBins& bins, const CellTexture& texture) {
  if (texture.action == CellTextureAction::WindowCentres) return std::nullopt;
  if (texture.action == CellTextureAction::AlbedoNormalised && !texture.albedoFactors.empty())
    return withCellsNormalised(bins, texture.albedoFactors);
  return bins;
}

}  // namespace slicecap::capture
