// The session journal's records as JSON: the slice object, an HDR sample's reading, whole numbers
// read without undefined behaviour, and the journal's file names.
#pragma once

#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>

#include "slicecap/capture/capture_error.hpp"
#include "slicecap/capture/frame_sample.hpp"
#include "slicecap/core/slice.hpp"

namespace slicecap::capture::journal_records {

inline constexpr const char* kJournal = "journal";
/// Left in a session folder whose journal was missing when it was opened: the loss is said on
/// every later open, not only the first.
inline constexpr const char* kJournalMissing = "journal.missing";

/// \brief {"kind", "theta_i", "theta_v"}.
nlohmann::json sliceJson(const SliceId& s);

/// \brief A whole number in lo..hi. nlohmann's get<int>() of 1e300 is undefined behaviour and its
/// get<std::uint64_t>() of -1 wraps round, so a damaged record would not be named. Throws
/// CaptureError naming the key, nlohmann::json::exception when it is missing.
template <typename T>
T wholeNumber(const nlohmann::json& parent, const std::string& key, T lo, T hi) {
  const nlohmann::json& value = parent.at(key);
  const auto within = [&](auto v) {
    return std::cmp_greater_equal(v, lo) && std::cmp_less_equal(v, hi);
  };
  if (value.is_number_unsigned() && within(value.get<std::uint64_t>()))
    return static_cast<T>(value.get<std::uint64_t>());
  if (value.is_number_integer() && !value.is_number_unsigned() && within(value.get<std::int64_t>()))
    return static_cast<T>(value.get<std::int64_t>());
  throw CaptureError(key + ": expected a whole number in " + std::to_string(lo) + ".." +
                     std::to_string(hi) + ", got " + value.dump());
}

template <typename T>
T wholeNumber(const nlohmann::json& parent, const std::string& key) {
  return wholeNumber(parent, key, std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
}

/// \brief The slice of sliceJson. Throws CaptureError or nlohmann::json::exception.
SliceId sliceFrom(const nlohmann::json& j);

/// \brief An HDR sample's reading as the sample record's "hdr" object (docs/reliability.md):
/// {"level", "cells": [[r, g, b, var r, var g, var b, level, clipped], ...], "irradiance",
/// "irradiance_weight"}. Doubles are written in their shortest form that reads back bit-identical.
nlohmann::json hdrJson(const HdrReading& hdr);

/// \brief The reading of hdrJson, checked by requireValidHdr. Throws CaptureError naming
/// the field (e.g. "hdr.cells[4][3]: expected a number, got null").
HdrReading hdrFrom(const nlohmann::json& j);

/// \brief Throws CaptureError naming the field unless the reading is one an HDR sweep
/// makes: kHdrCellsPerSide^2 cells, every number finite, variances >= 0, cell levels within
/// 0..kHdrMaxCellLevel, an exposure level within 0..io::kMaxExposureLevels - 1, an irradiance
/// weight >= 0.
void requireValidHdr(const HdrReading& hdr);

/// \brief A sample's window cells as the sample record's "cells" object (docs/reliability.md):
/// {"n", "grid_mm": [x0, y0, x1, y1], "light_mm": [x, y, z], "camera_mm": [x, y, z], "values":
/// [[r, g, b, var r, var g, var b, clipped 0|1], ...]}. The directions are not written: replay
/// recomputes them from the geometry (placeCellDirections), the same doubles giving the same
/// directions; values and variances are kept at cellPrecision and written in their short form.
nlohmann::json cellsJson(const WindowCells& cells);

/// \brief The cells of cellsJson, checked by requireValidCells, directions placed. Throws
/// CaptureError naming the field (e.g. "cells.values[4][3]: expected a number").
WindowCells cellsFrom(const nlohmann::json& j);

/// \brief Throws CaptureError naming the field unless the cells would replay: 1 to
/// kMaxCellsPerSide per side and that many squared cells, every number finite, variances >= 0,
/// the light and the camera above the target.
void requireValidCells(const WindowCells& cells);

inline constexpr int kMaxCellsPerSide = 32;

/// \brief A cell's level is a fraction of full scale as exposed: at most 1 but for rounding (the
/// mean per unit exposure times the exposure); a level beyond this is no reading.
inline constexpr double kHdrMaxCellLevel = 2.0;

}  // namespace slicecap::capture::journal_records
