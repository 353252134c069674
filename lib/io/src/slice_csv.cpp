// Slice CSV reading (strict, with file:line errors) and writing.
#include "slicecap/io/slice_csv.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "input_file.hpp"
#include "slicecap/core/angles.hpp"
#include "slicecap/core/version.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"

namespace slicecap::io {
namespace {

constexpr std::array<const char*, 8> kColumns{"slice", "theta_i", "phi_i", "theta_v",
                                              "phi_v", "r",       "g",     "b"};

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string_view> splitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

// How far a sample's azimuths may stray from its slice's relation before the row is taken for a
// wrong slice kind: three 15 deg bins. A capture's light direction is measured (fitted to the
// reference patches), and a light held off its nominal place is a poor sweep, not a wrong file:
// its samples stay usable by the methods that take actual angles (the prior).
constexpr double kSliceRelationToleranceDeg = 45.0;

int nearestRingDeg(double thetaDeg) {
  const int rounded = static_cast<int>(std::lround(thetaDeg / 15.0)) * 15;
  return std::clamp(rounded, 0, 75);
}

// A line of the CSV being read: errors name it as "source:line: what".
struct CsvLine {
  const std::string& sourceName;
  int number = 0;
  IoError error(const std::string& what) const {
    return IoError(sourceName + ":" + std::to_string(number) + ": " + what);
  }
};

using ColumnIndex = std::array<int, kColumns.size()>;  // field index of each of kColumns

ColumnIndex columnsOfHeader(const std::vector<std::string_view>& fields, const CsvLine& at) {
  ColumnIndex columnOf{};
  for (std::size_t k = 0; k < kColumns.size(); ++k) {
    columnOf[k] = -1;
    for (std::size_t f = 0; f < fields.size(); ++f) {
      if (fields[f] == kColumns[k]) columnOf[k] = static_cast<int>(f);
    }
    if (columnOf[k] < 0) {
      throw at.error(std::string("header has no column '") + kColumns[k] +
                     "' (expected slice,theta_i,phi_i,theta_v,phi_v,r,g,b)");
    }
  }
  return columnOf;
}

// The numeric columns (theta_i, phi_i, theta_v, phi_v, r, g, b) of a row, in that order; the
// elevations held to [0, 90) deg.
std::array<double, 7> numbersOfRow(const std::vector<std::string_view>& fields,
                                   const ColumnIndex& columnOf, const CsvLine& at) {
  std::array<double, 7> numbers{};
  for (std::size_t k = 1; k < kColumns.size(); ++k) {
    const std::string_view field = fields[columnOf[k]];
    double value = 0.0;
    const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
    if (ec != std::errc() || end != field.data() + field.size() || field.empty()) {
      throw at.error(std::string("column ") + kColumns[k] + ": '" + std::string(field) +
                     "' is not a number");
    }
    if (!std::isfinite(value))
      throw at.error(std::string("column ") + kColumns[k] + " is not finite");
    numbers[k - 1] = value;
  }
  for (std::size_t k : {1u, 3u}) {
    if (numbers[k - 1] < 0.0 || numbers[k - 1] >= 90.0) {
      throw at.error(std::string(kColumns[k]) + " " + std::string(fields[columnOf[k]]) +
                     " is outside [0, 90) deg");
    }
  }
  return numbers;
}

// Method B places a sample by one azimuth of it (axial: phi_i, diagonal: phi_v); a row whose
// other azimuth says another kind would land silently in the wrong place. Near the pole the
// azimuth means nothing, so only off-pole rows are held to their relation.
void checkSliceRelation(SliceKind kind, const ElevationPair& elevations, double phiIDeg,
                        double phiVDeg, const CsvLine& at) {
  if (kind != SliceKind::Point && elevations.thetaIDeg > 0 && elevations.thetaVDeg > 0) {
    const bool axial = kind == SliceKind::Axial;
    const double offDeg = axial ? azimuthDifferenceDeg(phiVDeg, phiIDeg + kAxialOffsetDeg)
                                : azimuthDifferenceDeg(phiVDeg, -phiIDeg);
    if (std::abs(offDeg) > kSliceRelationToleranceDeg) {
      char measured[32];
      std::snprintf(measured, sizeof measured, "%.1f",
                    axial ? azimuthDifferenceDeg(phiVDeg, phiIDeg) : wrapDeg360(phiIDeg + phiVDeg));
      throw at.error(std::string(toString(kind)) + " sample with " +
                     (axial ? "phi_v - phi_i = " : "phi_i + phi_v = ") + measured + " deg, " +
                     (axial ? "not 15" : "not 0 or 360") +
                     " deg: is its slice kind right? (a sample on no slice is 'point')");
    }
  }
}

// One sample row, checked, added to `slices`.
void addSampleRow(const std::vector<std::string_view>& fields, std::size_t headerFields,
                  const ColumnIndex& columnOf, const CsvLine& at, SliceSet& slices) {
  if (fields.size() != headerFields) {
    throw at.error("expected " + std::to_string(headerFields) + " fields, got " +
                   std::to_string(fields.size()) + " (truncated line?)");
  }
  const std::string_view kindText = fields[columnOf[0]];
  const auto kind = parseSliceKind(kindText);
  if (!kind)
    throw at.error("unknown slice kind '" + std::string(kindText) +
                   "' (expected axial, diagonal or point)");
  const std::array<double, 7> numbers = numbersOfRow(fields, columnOf, at);
  const double thetaIDeg = numbers[0], phiIDeg = numbers[1], thetaVDeg = numbers[2],
               phiVDeg = numbers[3];
  const ElevationPair elevations = nominalElevations(thetaIDeg, thetaVDeg);
  checkSliceRelation(*kind, elevations, phiIDeg, phiVDeg, at);
  slices.add({*kind, elevations},
             {{thetaIDeg, phiIDeg}, {thetaVDeg, phiVDeg}, {numbers[4], numbers[5], numbers[6]}});
}

}  // namespace

ElevationPair nominalElevations(double thetaIDeg, double thetaVDeg) {
  return {nearestRingDeg(thetaIDeg), nearestRingDeg(thetaVDeg)};
}

SliceSet parseSliceCsv(std::istream& in, const std::string& sourceName) {
  std::string line;
  CsvLine at{sourceName, 0};
  ColumnIndex columnOf{};
  std::size_t headerFields = 0;
  bool haveHeader = false;
  SliceSet slices;
  while (std::getline(in, line)) {
    ++at.number;
    // Spreadsheet programs save "CSV UTF-8" with a byte order mark before the header.
    constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";
    if (at.number == 1 && line.starts_with(kUtf8Bom)) line.erase(0, kUtf8Bom.size());
    const std::string_view text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    const std::vector<std::string_view> fields = splitFields(text);
    if (!haveHeader) {
      headerFields = fields.size();
      columnOf = columnsOfHeader(fields, at);
      haveHeader = true;
      continue;
    }
    addSampleRow(fields, headerFields, columnOf, at, slices);
  }
  if (in.bad()) throw IoError(sourceName + ": read error");
  if (!haveHeader) throw IoError(sourceName + ": empty slice CSV (no header line)");
  if (slices.empty()) throw IoError(sourceName + ": slice CSV has a header but no samples");
  return slices;
}

SliceSet readSliceCsv(const std::filesystem::path& path) {
  refuseDirectory(path, "a slice CSV");
  std::ifstream in(path);
  if (!in) throw IoError(path.string() + ": cannot open slice CSV");
  return parseSliceCsv(in, path.string());
}

void writeSliceCsv(std::ostream& out, const SliceSet& slices) {
  out << "# slicecap " << kVersion
      << " slice samples; angles in degrees, r,g,b linear BRDF in 1/sr\n";
  out << "slice,theta_i,phi_i,theta_v,phi_v,r,g,b\n";
  char buffer[256];
  for (const Slice& slice : slices.slices()) {
    for (const SliceSample& s : slice.samples) {
      std::snprintf(buffer, sizeof buffer, "%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                    std::string(toString(slice.id.kind)).c_str(), s.light.thetaDeg, s.light.phiDeg,
                    s.view.thetaDeg, s.view.phiDeg, s.value.r(), s.value.g(), s.value.b());
      out << buffer;
    }
  }
}

void writeSliceCsv(const std::filesystem::path& path, const SliceSet& slices) {
  writeStreamReplacing(path, [&](std::ostream& out) { writeSliceCsv(out, slices); });
}

}  // namespace slicecap::io
