// A running sweep's texture verdict, judged again as its frames grow (docs/method.md §9.5).
#include "slicecap/capture/window_cell_texture.hpp"

#include <algorithm>
#include <utility>

namespace slicecap::capture {
namespace {

std::size_t framesWithCells(const AzimuthBins& bins) {
  std::size_t count = 0;
  for (int b = 0; b < bins.binCount(); ++b)
    for (const FrameSample& frame : bins.samplesIn(b)) count += frame.cells ? 1 : 0;
  return count;
}

}  // namespace

RunningCellTexture::RunningCellTexture(CellTextureRule rule, double regrowth)
    : rule_(std::move(rule)), regrowth_(regrowth) {}

const CellTexture& RunningCellTexture::of(const AzimuthBins& bins) {
  const std::size_t frames = framesWithCells(bins);
  // Growth by a factor keeps the judgements' total cost a few times one judgement of the whole
  // sweep. Another run (the slice redone, even if its frames have regrown past the kept count
  // with no verdict asked in between) is not the kept verdict's: judged afresh.
  const bool otherRun = runJudged_ != bins.run();
  const bool grown = frames > framesJudged_ && double(frames) >= regrowth_ * double(framesJudged_);
  if (otherRun || grown) {
    texture_ = cellTextureOf(bins, rule_);
    framesJudged_ = frames;
    runJudged_ = bins.run();
    // Too few frames for any verdict: the first frames of a textured sweep would otherwise name
    // its thread a missed peak. Once there are enough, a verdict of too few frames clear of the
    // noise reads the cells as they are, as a finished sweep's does.
    if (frames < std::size_t(std::max(rule_.minFrames, 1)))
      texture_.action = CellTextureAction::WindowCentres;
  }
  return texture_;
}

}  // namespace slicecap::capture
