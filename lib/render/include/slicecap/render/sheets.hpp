// The pictures a person looks at: the evaluation sheet of one material and the preview of a table.
#pragma once

#include <string>
#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/grid.hpp"
#include "slicecap/render/canvas.hpp"

namespace slicecap::render {

/// \brief One reconstruction on an evaluation sheet, with the lines of text under it (e.g. its
/// metrics).
struct SheetPanel {
  std::string title;
  const Abrdf* table = nullptr;
  std::vector<std::string> lines;
};

/// \brief The evaluation sheet: a heading, then the reference and every reconstruction in the
/// 81 x 81 layout (paper's Fig. 1, encoded against the reference's maximum), each reconstruction
/// above its x10 difference to the reference, and the panel's lines under it. Throws
/// RenderError for a reference without a positive value or a panel without a table.
Canvas evaluationSheet(const std::string& heading, const Abrdf& reference,
                       const std::vector<std::string>& referenceLines,
                       const std::vector<SheetPanel>& panels);

/// \brief The light directions of the preview's spheres (theta from the viewing axis, phi
/// counter-clockwise from the picture's right).
inline const std::vector<Direction>& previewLights() {
  static const std::vector<Direction> lights{{20, 135}, {45, 45}, {65, 200}, {80, 300}};
  return lights;
}

/// \brief The preview: a heading and lines of text, the table in the 81 x 81 layout (normalised
/// to its own maximum) and spheres lit from previewLights(). Throws RenderError for a
/// table without a positive value.
Canvas previewSheet(const std::string& heading, const std::vector<std::string>& lines,
                    const Abrdf& table);

}  // namespace slicecap::render
