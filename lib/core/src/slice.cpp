// Slice kinds, ids and the SliceSet container.
#include "slicecap/core/slice.hpp"

#include <algorithm>
#include <stdexcept>

#include "slicecap/core/angles.hpp"
#include "slicecap/core/core_error.hpp"

namespace slicecap {

std::string_view toString(SliceKind kind) {
  switch (kind) {
    case SliceKind::Axial:
      return "axial";
    case SliceKind::Diagonal:
      return "diagonal";
    case SliceKind::Point:
      return "point";
  }
  return "unknown";
}

std::optional<SliceKind> parseSliceKind(std::string_view text) {
  if (text == "axial") return SliceKind::Axial;
  if (text == "diagonal") return SliceKind::Diagonal;
  if (text == "point") return SliceKind::Point;
  return std::nullopt;
}

std::string toString(const SliceId& id) {
  return std::string(toString(id.kind)) + " " + std::to_string(id.elevations.thetaIDeg) + "/" +
         std::to_string(id.elevations.thetaVDeg);
}

std::string folderName(const SliceId& id) {
  return std::string(toString(id.kind)) + "-" + std::to_string(id.elevations.thetaIDeg) + "-" +
         std::to_string(id.elevations.thetaVDeg);
}

double sliceParameterDeg(SliceKind kind, const SliceSample& sample) {
  if (kind == SliceKind::Point) throw CoreError("a point sample lies on no slice");
  return wrapDeg360(kind == SliceKind::Axial ? sample.light.phiDeg : sample.view.phiDeg);
}

AzimuthPair slicePoint(SliceKind kind, double parameterDeg) {
  if (kind == SliceKind::Point) throw CoreError("a point sample lies on no slice");
  if (kind == SliceKind::Axial) {
    return {wrapDeg360(parameterDeg), wrapDeg360(parameterDeg + kAxialOffsetDeg)};
  }
  return {wrapDeg360(360.0 - parameterDeg), wrapDeg360(parameterDeg)};
}

void SliceSet::add(const SliceId& id, const SliceSample& sample) {
  auto it = std::lower_bound(slices_.begin(), slices_.end(), id,
                             [](const Slice& s, const SliceId& key) { return s.id < key; });
  if (it == slices_.end() || it->id != id) it = slices_.insert(it, Slice{id, {}});
  it->samples.push_back(sample);
}

void SliceSet::addCellSample(const SliceId& id, const SliceSample& sample) {
  auto it = std::lower_bound(slices_.begin(), slices_.end(), id,
                             [](const Slice& s, const SliceId& key) { return s.id < key; });
  if (it == slices_.end() || it->id != id)
    throw CoreError("slice " + toString(id) +
                    ": a cell sample for a slice without samples");
  it->cellSamples.push_back(sample);
}

void SliceSet::addCellFrame(const SliceId& id, FrameCellPoints cells) {
  auto it = std::lower_bound(slices_.begin(), slices_.end(), id,
                             [](const Slice& s, const SliceId& key) { return s.id < key; });
  if (it == slices_.end() || it->id != id)
    throw CoreError("slice " + toString(id) + ": cells of a frame for a slice without samples");
  if (!cells.empty()) it->cellFrames.push_back(std::move(cells));
}

bool SliceSet::hasCellFrames() const {
  return std::any_of(slices_.begin(), slices_.end(),
                     [](const Slice& s) { return !s.cellFrames.empty(); });
}

bool SliceSet::hasCellSamples() const {
  return std::any_of(slices_.begin(), slices_.end(),
                     [](const Slice& s) { return !s.cellSamples.empty(); });
}

SliceSet SliceSet::cellReading() const {
  SliceSet out;
  for (const Slice& s : slices_)
    out.slices_.push_back(
        {s.id, s.cellSamples.empty() ? s.samples : s.cellSamples, {}, s.cellFrames});
  return out;
}

const Slice* SliceSet::find(const SliceId& id) const {
  auto it = std::lower_bound(slices_.begin(), slices_.end(), id,
                             [](const Slice& s, const SliceId& key) { return s.id < key; });
  return (it != slices_.end() && it->id == id) ? &*it : nullptr;
}

std::size_t SliceSet::sampleCount() const {
  std::size_t count = 0;
  for (const Slice& s : slices_)
    count += s.samples.size();
  return count;
}

}  // namespace slicecap
