// The session journal's records as JSON.
#include "journal_records.hpp"

#include <array>
#include <charconv>
#include <cmath>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/window_cells.hpp"
#include "slicecap/io/recording.hpp"

namespace slicecap::capture::journal_records {
namespace {

using nlohmann::json;

// A cell's array, in order: what each position holds (named in errors).
constexpr std::array<const char*, 8> kCellFields = {"radiance r", "radiance g", "radiance b",
                                                    "variance r", "variance g", "variance b",
                                                    "level",      "clipped"};
constexpr std::size_t kClippedField = 7;
constexpr std::size_t kCellCount = std::size_t(kHdrCellsPerSide) * kHdrCellsPerSide;

// The shortest form that reads back as `value` (as the journal writes it): -1e-06, not
// -9.9999999999999995e-07.
std::string text(double value) {
  char out[32];
  const std::to_chars_result end = std::to_chars(out, out + sizeof out, value);
  return std::string(out, end.ptr);
}

std::string cellField(std::size_t cell, std::size_t field) {
  return "hdr.cells[" + std::to_string(cell) + "][" + std::to_string(field) + "] (" +
         kCellFields[field] + ")";
}

const json& member(const json& hdr, const std::string& key) {
  if (!hdr.contains(key)) throw CaptureError("hdr." + key + ": missing");
  return hdr.at(key);
}

double number(const json& value, const std::string& name) {
  if (!value.is_number())
    throw CaptureError(name + ": expected a number, got " + value.dump());
  return value.get<double>();
}

void requireFinite(double value, const std::string& name) {
  if (!std::isfinite(value))
    throw CaptureError(name + ": expected a finite number, got " + text(value));
}

HdrCell cellFrom(const json& j, std::size_t k) {
  if (!j.is_array() || j.size() != kCellFields.size())
    throw CaptureError("hdr.cells[" + std::to_string(k) +
                       "]: expected [r, g, b, variance r, g, b, level, clipped], got " +
                       j.dump());
  HdrCell cell;
  for (std::size_t c = 0; c < 3; ++c) {
    cell.radiance[c] = number(j[c], cellField(k, c));
    cell.variance[c] = number(j[3 + c], cellField(k, 3 + c));
  }
  cell.level = number(j[6], cellField(k, 6));
  if (!j[kClippedField].is_boolean())
    throw CaptureError(cellField(k, kClippedField) + ": expected true or false, got " +
                       j[kClippedField].dump());
  cell.clipped = j[kClippedField].get<bool>();
  return cell;
}

}  // namespace

json sliceJson(const SliceId& s) {
  return {{"kind", toString(s.kind)},
          {"theta_i", s.elevations.thetaIDeg},
          {"theta_v", s.elevations.thetaVDeg}};
}

SliceId sliceFrom(const json& j) {
  const auto kind = parseSliceKind(j.at("kind").get<std::string>());
  if (!kind) throw CaptureError("unknown slice kind");
  return {*kind, {wholeNumber(j, "theta_i", 0, 89), wholeNumber(j, "theta_v", 0, 89)}};
}

// Arrays, not objects, per cell: 36 cells x 8 values make most of an HDR sample's record (see
// docs/reliability.md for its size), and each record is one synced line.
json hdrJson(const HdrReading& hdr) {
  json cells = json::array();
  for (const HdrCell& c : hdr.cells)
    cells.push_back(json::array({c.radiance[0], c.radiance[1], c.radiance[2], c.variance[0],
                                 c.variance[1], c.variance[2], c.level, c.clipped}));
  return {{"exposure_level", hdr.exposureLevel},
          {"cells", std::move(cells)},
          {"irradiance", json::array({hdr.irradiance[0], hdr.irradiance[1], hdr.irradiance[2]})},
          {"irradiance_weight", hdr.irradianceWeight}};
}

HdrReading hdrFrom(const json& j) {
  if (!j.is_object()) throw CaptureError("hdr: expected an object, got " + j.dump());
  HdrReading hdr;
  static_cast<void>(member(j, "exposure_level"));
  try {
    hdr.exposureLevel = wholeNumber(j, "exposure_level", 0, io::kMaxExposureLevels - 1);
  } catch (const CaptureError& e) {
    throw CaptureError(std::string("hdr.") + e.what());
  }
  const json& cells = member(j, "cells");
  if (!cells.is_array() || cells.size() != kCellCount)
    throw CaptureError(
        "hdr.cells: expected an array of " + std::to_string(kCellCount) + " cells, got " +
        (cells.is_array() ? std::to_string(cells.size()) + " cells" : cells.dump()));
  for (std::size_t k = 0; k < cells.size(); ++k)
    hdr.cells.push_back(cellFrom(cells[k], k));
  const json& irradiance = member(j, "irradiance");
  if (!irradiance.is_array() || irradiance.size() != 3)
    throw CaptureError("hdr.irradiance: expected [r, g, b], got " + irradiance.dump());
  for (std::size_t c = 0; c < 3; ++c)
    hdr.irradiance[c] = number(irradiance[c], "hdr.irradiance[" + std::to_string(c) + "]");
  hdr.irradianceWeight = number(member(j, "irradiance_weight"), "hdr.irradiance_weight");
  requireValidHdr(hdr);
  return hdr;
}

void requireValidHdr(const HdrReading& hdr) {
  if (hdr.exposureLevel < 0 || hdr.exposureLevel >= io::kMaxExposureLevels)
    throw CaptureError("hdr.exposure_level: expected 0.." +
                       std::to_string(io::kMaxExposureLevels - 1) + ", got " +
                       std::to_string(hdr.exposureLevel));
  if (hdr.cells.size() != kCellCount)
    throw CaptureError("hdr.cells: expected " + std::to_string(kCellCount) +
                       " cells, got " + std::to_string(hdr.cells.size()));
  for (std::size_t k = 0; k < hdr.cells.size(); ++k) {
    const HdrCell& cell = hdr.cells[k];
    for (std::size_t c = 0; c < 3; ++c) {
      requireFinite(cell.radiance[c], cellField(k, c));
      requireFinite(cell.variance[c], cellField(k, 3 + c));
      if (cell.variance[c] < 0)
        throw CaptureError(cellField(k, 3 + c) + ": expected a variance >= 0, got " +
                           text(cell.variance[c]));
    }
    requireFinite(cell.level, cellField(k, 6));
    if (cell.level < 0 || cell.level > kHdrMaxCellLevel)
      throw CaptureError(cellField(k, 6) + ": expected a fraction of full scale in 0.." +
                         text(kHdrMaxCellLevel) + ", got " + text(cell.level));
  }
  for (std::size_t c = 0; c < 3; ++c)
    requireFinite(hdr.irradiance[c], "hdr.irradiance[" + std::to_string(c) + "]");
  requireFinite(hdr.irradianceWeight, "hdr.irradiance_weight");
  if (hdr.irradianceWeight < 0)
    throw CaptureError("hdr.irradiance_weight: expected >= 0, got " +
                       text(hdr.irradianceWeight));
}

// Window cells: arrays per cell as for HDR cells (64 cells make most of the record), clipped as
// 0 or 1.
json cellsJson(const WindowCells& cells) {
  json values = json::array();
  for (const CellSample& c : cells.cells)
    values.push_back(json::array({c.value[0], c.value[1], c.value[2], c.variance[0],
                                  c.variance[1], c.variance[2], c.clipped ? 1 : 0}));
  return {{"n", cells.cellsPerSide},
          {"grid_mm", cells.gridMm},
          {"light_mm", cells.lightMm},
          {"camera_mm", cells.cameraMm},
          {"values", std::move(values)}};
}

namespace {

template <std::size_t N>
std::array<double, N> numbers(const json& parent, const std::string& key) {
  const std::string name = "cells." + key;
  if (!parent.contains(key)) throw CaptureError(name + ": missing");
  const json& j = parent.at(key);
  if (!j.is_array() || j.size() != N)
    throw CaptureError(name + ": expected " + std::to_string(N) + " numbers, got " +
                       j.dump());
  std::array<double, N> out{};
  for (std::size_t k = 0; k < N; ++k)
    out[k] = number(j[k], name + "[" + std::to_string(k) + "]");
  return out;
}

std::string cellValueField(std::size_t cell, std::size_t field) {
  static constexpr std::array<const char*, 7> kFields = {
      "value r", "value g", "value b", "variance r", "variance g", "variance b", "clipped"};
  return "cells.values[" + std::to_string(cell) + "][" + std::to_string(field) + "] (" +
         kFields[field] + ")";
}

}  // namespace

WindowCells cellsFrom(const json& j) {
  if (!j.is_object()) throw CaptureError("cells: expected an object, got " + j.dump());
  WindowCells cells;
  if (!j.contains("n")) throw CaptureError("cells.n: missing");
  try {
    cells.cellsPerSide = wholeNumber(j, "n", 1, kMaxCellsPerSide);
  } catch (const CaptureError& e) {
    throw CaptureError(std::string("cells.") + e.what());
  }
  cells.gridMm = numbers<4>(j, "grid_mm");
  cells.lightMm = numbers<3>(j, "light_mm");
  cells.cameraMm = numbers<3>(j, "camera_mm");
  if (!j.contains("values")) throw CaptureError("cells.values: missing");
  const json& values = j.at("values");
  const std::size_t count = std::size_t(cells.cellsPerSide) * std::size_t(cells.cellsPerSide);
  if (!values.is_array() || values.size() != count)
    throw CaptureError("cells.values: expected " + std::to_string(count) +
                       " cells, got " + values.dump().substr(0, 80));
  for (std::size_t k = 0; k < count; ++k) {
    const json& v = values[k];
    if (!v.is_array() || v.size() != 7)
      throw CaptureError("cells.values[" + std::to_string(k) +
                         "]: expected [r, g, b, variance r, g, b, clipped], got " +
                         v.dump());
    CellSample cell;
    for (std::size_t c = 0; c < 3; ++c) {
      cell.value[c] = number(v[c], cellValueField(k, c));
      cell.variance[c] = number(v[3 + c], cellValueField(k, 3 + c));
    }
    if (!(v[6] == 0 || v[6] == 1))
      throw CaptureError(cellValueField(k, 6) + ": expected 0 or 1, got " + v[6].dump());
    cell.clipped = v[6] == 1;
    cells.cells.push_back(cell);
  }
  requireValidCells(cells);
  placeCellDirections(cells);
  return cells;
}

void requireValidCells(const WindowCells& cells) {
  const int n = cells.cellsPerSide;
  if (n < 1 || n > kMaxCellsPerSide)
    throw CaptureError("cells.n: expected 1.." + std::to_string(kMaxCellsPerSide) +
                       ", got " + std::to_string(n));
  if (cells.cells.size() != std::size_t(n) * std::size_t(n))
    throw CaptureError("cells.values: expected " + std::to_string(n * n) +
                       " cells, got " + std::to_string(cells.cells.size()));
  for (std::size_t k = 0; k < 4; ++k)
    requireFinite(cells.gridMm[k], "cells.grid_mm[" + std::to_string(k) + "]");
  for (std::size_t k = 0; k < 3; ++k) {
    requireFinite(cells.lightMm[k], "cells.light_mm[" + std::to_string(k) + "]");
    requireFinite(cells.cameraMm[k], "cells.camera_mm[" + std::to_string(k) + "]");
  }
  if (!(cells.lightMm[2] > 0.0) || !(cells.cameraMm[2] > 0.0))
    throw CaptureError("cells: light_mm and camera_mm must lie above the target (z > 0)");
  for (std::size_t k = 0; k < cells.cells.size(); ++k)
    for (std::size_t c = 0; c < 3; ++c) {
      requireFinite(cells.cells[k].value[c], cellValueField(k, c));
      requireFinite(cells.cells[k].variance[c], cellValueField(k, 3 + c));
      if (cells.cells[k].variance[c] < 0)
        throw CaptureError(cellValueField(k, 3 + c) + ": expected a variance >= 0, got " +
                           text(cells.cells[k].variance[c]));
    }
}

}  // namespace slicecap::capture::journal_records
