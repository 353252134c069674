// The printable target as SVG, PDF (a page with instructions) or PNG (the sheet alone), true scale.
#pragma once

#include <filesystem>

#include "slicecap/core/image.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::io {

/// \brief The paper the SVG and PDF pages are laid out on.
enum class PaperSize { A4, Letter };

/// \brief Writes an SVG page (width and height in mm, viewBox in mm) with the target centred near
/// the top, its window's cut line dashed, a 100 mm scale bar and the printing instructions.
/// Throws IoError naming the path when it cannot be written or the sheet does not fit the page;
/// an old file at `path` is then left as it was (these writers go through a temporary).
void writeTargetSvg(const std::filesystem::path& path, const vision::TargetGeometry& target,
                    PaperSize paper = PaperSize::A4);

/// \brief The same page as a one-page PDF 1.4 (vector; Helvetica, not embedded).
void writeTargetPdf(const std::filesystem::path& path, const vision::TargetGeometry& target,
                    PaperSize paper = PaperSize::A4);

/// \brief The sheet alone as an 8-bit gray image at `dpi`: ink 0, paper 255, box-filtered edges,
/// the window's outline mid-grey. Pixel (i, j) covers x in sheet.xMin + [i, i + 1) * 25.4 / dpi
/// and y in sheet.yMax - [j, j + 1) * 25.4 / dpi. Throws IoError for dpi outside
/// 50..2400.
Image renderTargetImage(const vision::TargetGeometry& target, double dpi);

/// \brief renderTargetImage written as PNG with its dpi in the pHYs chunk (so it prints at true
/// scale). Throws IoError naming the path.
void writeTargetPng(const std::filesystem::path& path, const vision::TargetGeometry& target,
                    double dpi);

}  // namespace slicecap::io
