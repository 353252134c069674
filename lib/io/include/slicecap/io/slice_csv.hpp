// Slice CSV: `slice,theta_i,phi_i,theta_v,phi_v,r,g,b`, one sample a line, degrees and linear BRDF.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

#include "slicecap/core/slice.hpp"

namespace slicecap::io {

/// \brief The nominal elevation pair of a sample: each elevation rounded to the nearest Bonn ring
/// (0, 15, ..., 75). A capture gates samples within a few degrees of the nominal pair.
ElevationPair nominalElevations(double thetaIDeg, double thetaVDeg);

/// \brief Parses slice CSV text. The header names the columns (any order; extra columns are
/// ignored); lines starting with '#' and blank lines are skipped, and so is a UTF-8 byte order
/// mark at the start (as spreadsheet programs write it). Every error throws IoError as
/// "SOURCE:LINE: what" (a truncated row, a non-numeric or non-finite field, an unknown slice kind,
/// an elevation outside [0, 90), no samples at all, a row whose azimuths contradict its kind by
/// more than 45 deg: axial needs phi_v - phi_i = 15 deg, diagonal phi_i + phi_v = 0 mod 360;
/// rows with an elevation on the 0 deg ring are exempt, their azimuths mean nothing).
SliceSet parseSliceCsv(std::istream& in, const std::string& sourceName);

/// \brief Reads a slice CSV file; errors as parseSliceCsv, or IoError naming the path when it
/// cannot be opened or is a directory.
SliceSet readSliceCsv(const std::filesystem::path& path);

/// \brief Writes every sample of every slice (with a `#` comment line naming the writer); angles in
/// degrees, values with 9 significant digits. Throws IoError naming the path on failure, which
/// leaves an old file at `path` as it was (written through a temporary: file_replacement.hpp).
void writeSliceCsv(const std::filesystem::path& path, const SliceSet& slices);
void writeSliceCsv(std::ostream& out, const SliceSet& slices);

}  // namespace slicecap::io
