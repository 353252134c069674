// Composition of the evaluation sheet and the preview.
#include "slicecap/render/sheets.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/render/layout_image.hpp"
#include "slicecap/render/render_error.hpp"
#include "slicecap/render/sphere_render.hpp"

namespace slicecap::render {
namespace {

constexpr int kPixelsPerEntry = 3;
constexpr int kMargin = 12;
constexpr int kLineHeight = 11;
constexpr int kHeadingScale = 2;

double positiveMaximum(const Abrdf& table) {
  const double maximum = eval::cosWeightedMaximum(table);
  if (!(maximum > 0.0)) throw RenderError("the table has no positive value to show");
  return maximum;
}

// Lines of text at (x, y), clipped to `width` pixels; returns the y below them.
int drawLines(Canvas& canvas, int x, int y, const std::vector<std::string>& lines, int width,
              Colour colour) {
  const std::size_t fits = std::size_t(std::max(1, (width + 1) / 6));
  for (const std::string& line : lines) {
    canvas.drawText(x, y, line.size() > fits ? line.substr(0, fits - 1) + "~" : line, colour);
    y += kLineHeight;
  }
  return y;
}

int headingHeight() {
  return kMargin + textHeight(kHeadingScale) + kMargin;
}

}  // namespace

Canvas evaluationSheet(const std::string& heading, const Abrdf& reference,
                       const std::vector<std::string>& referenceLines,
                       const std::vector<SheetPanel>& panels) {
  const double referenceMax = positiveMaximum(reference);
  const int side = layoutSide(kPixelsPerEntry);
  std::size_t textLines = referenceLines.size() + 1;
  for (const SheetPanel& p : panels) {
    if (!p.table)
      throw RenderError("evaluation sheet: panel '" + p.title + "' has no table");
    textLines = std::max(textLines, p.lines.size() + 1);
  }
  const int column = side + kMargin;
  const int width = kMargin + column * int(1 + panels.size());
  const int textBlock = int(textLines) * kLineHeight + kMargin / 2;
  const int top = headingHeight();
  const int height = top + side + 4 + kLineHeight + side + 4 + textBlock + kMargin;
  Canvas sheet(width, height);
  sheet.drawText(kMargin, kMargin, heading, kText, kHeadingScale);

  // Reference column: the picture, then its lines where the reconstructions have differences.
  int x = kMargin;
  sheet.blit(layoutImage(reference, referenceMax, kPixelsPerEntry), x, top);
  int y = top + side + 4;
  sheet.drawText(x, y, "reference", kText);
  drawLines(sheet, x, y + kLineHeight, referenceLines, side, kDimText);
  sheet.drawText(x, top + side + 4 + kLineHeight + side + 4, "x10 differences below,", kDimText);
  sheet.drawText(x, top + side + 4 + 2 * kLineHeight + side + 4, "light rows, view columns",
                 kDimText);
  for (const SheetPanel& p : panels) {
    x += column;
    sheet.blit(layoutImage(*p.table, referenceMax, kPixelsPerEntry), x, top);
    sheet.drawText(x, top + side + 4, p.title, kText);
    y = top + side + 4 + kLineHeight;
    sheet.blit(differenceImage(reference, *p.table, referenceMax, 10, kPixelsPerEntry), x, y);
    drawLines(sheet, x, y + side + 4, p.lines, side, kText);
  }
  return sheet;
}

Canvas previewSheet(const std::string& heading, const std::vector<std::string>& lines,
                    const Abrdf& table) {
  const double maximum = positiveMaximum(table);
  const int side = layoutSide(kPixelsPerEntry);
  const int sphere = (side - kMargin) / 2;
  const std::vector<Direction>& lights = previewLights();
  const int width = kMargin + side + kMargin + 2 * (sphere + kMargin);
  const int top = headingHeight();
  const int textBlock = int(lines.size() + 1) * kLineHeight;
  const int height = top + side + kMargin + textBlock + kMargin;
  Canvas sheet(width, height);
  sheet.drawText(kMargin, kMargin, heading, kText, kHeadingScale);
  sheet.blit(layoutImage(table, maximum, kPixelsPerEntry), kMargin, top);
  const int sphereX = kMargin + side + kMargin;
  for (std::size_t k = 0; k < lights.size(); ++k) {
    const int x = sphereX + int(k % 2) * (sphere + kMargin);
    const int y = top + int(k / 2) * (sphere + kMargin);
    // The layout's white level: a sphere is as bright as the table's own maximum allows.
    sheet.blit(renderSphere(table, lights[k], sphere - kLineHeight, maximum), x, y);
    sheet.drawText(x, y + sphere - kLineHeight + 2,
                   "light " + std::to_string(int(std::lround(lights[k].thetaDeg))) + "/" +
                       std::to_string(int(std::lround(lights[k].phiDeg))),
                   kDimText);
  }
  std::vector<std::string> all{"81 x 81 layout: light rows, view columns, rings 0..75 deg"};
  all.insert(all.end(), lines.begin(), lines.end());
  drawLines(sheet, kMargin, top + side + kMargin, all, width - 2 * kMargin, kDimText);
  return sheet;
}

}  // namespace slicecap::render
