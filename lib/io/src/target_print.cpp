// One page drawing of the target, emitted as SVG or as a hand-written PDF; and the PNG raster.
#include "slicecap/io/target_print.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/vision/tag_family.hpp"
#include "slicecap/vision/target_surface.hpp"

namespace slicecap::io {
namespace {

using vision::PointMm;

// Page coordinates: mm from the page's top-left corner, y down (SVG's convention).
struct Polygon {
  std::vector<PointMm> points;
  bool filled = true;  ///< filled black, else stroked
  double strokeMm = 0.0;
  bool dashed = false;
  double gray = 0.0;  ///< 0 black .. 1 white
};
struct Text {
  PointMm at;  ///< baseline start
  double sizePt = 9.0;
  std::string text;
};
struct Page {
  double widthMm = 0.0, heightMm = 0.0;
  std::vector<Polygon> shapes;
  std::vector<Text> texts;
};

std::string fixed(double v, int decimals = 3) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string formatMm(double v) {
  std::string text = fixed(v, 2);
  text.erase(text.find_last_not_of('0') + 1);
  if (text.back() == '.') text.pop_back();
  return text;
}

// Where the sheet sits on the page: target mm (y up) to page mm (y down).
struct SheetPlacement {
  double originX = 0.0, originY = 0.0;
  PointMm toPage(double x, double y) const { return PointMm{originX + x, originY - y}; }
  std::vector<PointMm> rect(const vision::RectMm& r) const {
    return std::vector<PointMm>{toPage(r.xMinMm, r.yMinMm), toPage(r.xMaxMm, r.yMinMm),
                                toPage(r.xMaxMm, r.yMaxMm), toPage(r.xMinMm, r.yMaxMm)};
  }
};

// A marker's black cells, one filled shape per run of black cells in a row.
void addMarker(Page& page, const vision::Marker& m, const SheetPlacement& sheet) {
  const vision::TagBitmap bitmap = vision::tag36h11Bitmap(m.id);
  const PointMm o = m.cornersMm[0];
  const double cell = 1.0 / vision::kTagBorderCells;
  auto markerPoint = [&](double u, double v) {  // u, v in border cells from the bottom-left
    const double x =
        o.xMm + (m.cornersMm[1].xMm - o.xMm) * u * cell + (m.cornersMm[3].xMm - o.xMm) * v * cell;
    const double y =
        o.yMm + (m.cornersMm[1].yMm - o.yMm) * u * cell + (m.cornersMm[3].yMm - o.yMm) * v * cell;
    return sheet.toPage(x, y);
  };
  for (int row = 1; row <= vision::kTagBorderCells; ++row) {
    const double vTop = vision::kTagBorderCells - (row - 1);
    for (int column = 1; column <= vision::kTagBorderCells;) {
      if (bitmap[row][column]) {
        ++column;
        continue;
      }
      int end = column;
      while (end <= vision::kTagBorderCells && !bitmap[row][end])
        ++end;
      const double u0 = column - 1, u1 = end - 1;
      page.shapes.push_back({{markerPoint(u0, vTop - 1), markerPoint(u1, vTop - 1),
                              markerPoint(u1, vTop), markerPoint(u0, vTop)},
                             true, 0.0, false, 0.0});
      column = end;
    }
  }
}

// A 100 mm scale bar with its caption, at page height `y`; returns the height below it.
double addScaleBar(Page& page, double y) {
  const double barX = (page.widthMm - 100.0) / 2;
  page.shapes.push_back({{{barX, y}, {barX + 100.0, y}, {barX + 100.0, y + 2.0}, {barX, y + 2.0}},
                         true, 0.0, false, 0.0});
  for (double tick : {0.0, 50.0, 100.0})
    page.shapes.push_back({{{barX + tick - 0.2, y - 2.0}, {barX + tick + 0.2, y - 2.0},
                            {barX + tick + 0.2, y}, {barX + tick - 0.2, y}},
                           true, 0.0, false, 0.0});
  y += 7.0;
  page.texts.push_back({{barX, y}, 8.0, "This bar is 100 mm long. Measure it after printing."});
  return y;
}

// The printing and use instructions, from page height `y` down.
void addInstructions(Page& page, const vision::TargetGeometry& t, double y) {
  const double textX = 20.0;
  const std::string ids = std::to_string(t.markers.front().id) + "-" + std::to_string(t.markers.back().id);
  const std::vector<std::string> lines = {
        "slicecap target " + t.name,
        "Print at 100 % (actual size, no 'fit to page'), on matte white paper, with a laser printer.",
        "Window " + formatMm(t.window.widthMm()) + " x " + formatMm(t.window.heightMm()) + " mm (cut out along the dashed line); " +
            std::to_string(t.markers.size()) + " AprilTag tag36h11 markers, ids " + ids + ", " +
            formatMm(t.markers.front().sizeMm) + " mm.",
        std::string("Lay the sheet flat on the material, window over the area to capture. The white band"),
        std::string("around the window is the reference for the light; keep it clean and flat."),
        std::string("slicecap target --json writes this target's geometry (recordings embed it).")};
  for (const std::string& line : lines) {
    page.texts.push_back({{textX, y}, 9.0, line});
    y += 5.5;
  }
}

Page layOut(const vision::TargetGeometry& t, PaperSize paper, const std::filesystem::path& path) {
  Page page;
  page.widthMm = paper == PaperSize::A4 ? 210.0 : 215.9;
  page.heightMm = paper == PaperSize::A4 ? 297.0 : 279.4;
  const double topMm = 20.0;
  const double sheetW = t.sheet.widthMm(), sheetH = t.sheet.heightMm();
  if (sheetW > page.widthMm - 20.0 || sheetH > page.heightMm - topMm - 50.0)
    throw IoError(path.string() + ": the target's sheet (" + formatMm(sheetW) + " x " +
                  formatMm(sheetH) + " mm) does not fit the page with its instructions");
  const SheetPlacement sheet{(page.widthMm - sheetW) / 2 - t.sheet.xMinMm, topMm + t.sheet.yMaxMm};
  page.shapes.push_back({sheet.rect(t.sheet), false, 0.15, false, 0.7});
  page.shapes.push_back({sheet.rect(t.window), false, 0.3, true, 0.4});
  for (const vision::Patch& p : t.patches) {
    if (p.kind == vision::PatchKind::Black)
      page.shapes.push_back({sheet.rect(p.rect), true, 0.0, false, 0.0});
  }
  for (const vision::Marker& m : t.markers)
    addMarker(page, m, sheet);
  const PointMm windowCentre = sheet.toPage(t.window.centre().xMm, t.window.centre().yMm);
  page.texts.push_back({{windowCentre.xMm - 5.5, windowCentre.yMm + 1.0}, 7.0, "cut out"});

  // A 100 mm scale bar and the instructions under the sheet.
  const double belowBarY = addScaleBar(page, topMm + sheetH + 12.0);
  addInstructions(page, t, belowBarY + 10.0);
  return page;
}

std::string svgOf(const Page& page) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << formatMm(page.widthMm)
      << "mm\" height=\"" << formatMm(page.heightMm) << "mm\" viewBox=\"0 0 "
      << formatMm(page.widthMm) << " " << formatMm(page.heightMm) << "\">\n"
      << "<!-- slicecap printable target: print at 100 % (user units are mm) -->\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (const Polygon& s : page.shapes) {
    out << "<path d=\"M";
    for (const PointMm& p : s.points)
      out << " " << fixed(p.xMm) << " " << fixed(p.yMm);
    const int level = static_cast<int>(std::lround(s.gray * 255));
    const std::string colour = "rgb(" + std::to_string(level) + "," + std::to_string(level) + "," + std::to_string(level) + ")";
    out << " Z\"";
    if (s.filled) {
      out << " fill=\"" << colour << "\"/>\n";
    } else {
      out << " fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"" << fixed(s.strokeMm)
          << "\"" << (s.dashed ? " stroke-dasharray=\"2 1.5\"" : "") << "/>\n";
    }
  }
  for (const Text& t : page.texts) {
    std::string escaped;
    for (char c : t.text) {
      if (c == '<') escaped += "&lt;";
      else if (c == '>') escaped += "&gt;";
      else if (c == '&') escaped += "&amp;";
      else escaped += c;
    }
    out << "<text x=\"" << fixed(t.at.xMm) << "\" y=\"" << fixed(t.at.yMm)
        << "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\""
        << fixed(t.sizePt * 25.4 / 72.0) << "\">" << escaped << "</text>\n";
  }
  out << "</svg>\n";
  return out.str();
}

std::string pdfOf(const Page& page) {
  const double pt = 72.0 / 25.4;
  const double heightPt = page.heightMm * pt;
  std::ostringstream content;
  for (const Polygon& s : page.shapes) {
    content << fixed(s.gray, 3) << (s.filled ? " g\n" : " G\n");
    if (!s.filled) content << fixed(s.strokeMm * pt) << " w " << (s.dashed ? "[5.67 4.25] 0 d\n" : "[] 0 d\n");
    for (std::size_t i = 0; i < s.points.size(); ++i)
      content << fixed(s.points[i].xMm * pt) << " " << fixed(heightPt - s.points[i].yMm * pt)
              << (i == 0 ? " m\n" : " l\n");
    content << (s.filled ? "h f\n" : "h S\n");
  }
  content << "0 g\n";
  for (const Text& t : page.texts) {
    std::string escaped;
    for (char c : t.text) {
      if (c == '(' || c == ')' || c == '\\') escaped += '\\';
      escaped += c;
    }
    content << "BT /F1 " << fixed(t.sizePt, 1) << " Tf " << fixed(t.at.xMm * pt) << " "
            << fixed(heightPt - t.at.yMm * pt) << " Td (" << escaped << ") Tj ET\n";
  }
  const std::string stream = content.str();
  const std::vector<std::string> objects = {
      "<< /Type /Catalog /Pages 2 0 R >>",
      "<< /Type /Pages /Kids [3 0 R] /Count 1 >>",
      "<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + fixed(page.widthMm * pt) + " " +
          fixed(heightPt) + "] /Resources << /Font << /F1 5 0 R >> >> /Contents 4 0 R >>",
      "<< /Length " + std::to_string(stream.size()) + " >>\nstream\n" + stream + "endstream",
      "<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica /Encoding /WinAnsiEncoding >>"};
  std::string pdf = "%PDF-1.4\n%\xe2\xe3\xcf\xd3\n";
  std::vector<std::size_t> offsets;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    offsets.push_back(pdf.size());
    pdf += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
  }
  const std::size_t xref = pdf.size();
  pdf += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
  for (std::size_t offset : offsets) {
    char entry[32];
    std::snprintf(entry, sizeof entry, "%010zu 00000 n \n", offset);
    pdf += entry;
  }
  pdf += "trailer\n<< /Size " + std::to_string(objects.size() + 1) +
         " /Root 1 0 R >>\nstartxref\n" + std::to_string(xref) + "\n%%EOF\n";
  return pdf;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  writeStreamReplacing(path, [&](std::ostream& out) { out << text; });
}

}  // namespace

void writeTargetSvg(const std::filesystem::path& path, const vision::TargetGeometry& target,
                    PaperSize paper) {
  writeText(path, svgOf(layOut(target, paper, path)));
}

void writeTargetPdf(const std::filesystem::path& path, const vision::TargetGeometry& target,
                    PaperSize paper) {
  writeText(path, pdfOf(layOut(target, paper, path)));
}

Image renderTargetImage(const vision::TargetGeometry& target, double dpi) {
  if (!(dpi >= 50.0 && dpi <= 2400.0))
    throw IoError("dpi must be 50 to 2400, not " + formatMm(dpi));
  const double pixelsPerMm = dpi / 25.4;
  const vision::TargetRaster raster =
      vision::rasterizeTarget(vision::TargetSurface(target), target.sheet, pixelsPerMm, 4);
  Image image{raster.width, raster.height, 1, 8, {}};
  image.samples.resize(std::size_t(raster.width) * raster.height);
  const double ink = target.inkAlbedo.mean(), paper = target.paperAlbedo.mean();
  for (std::size_t i = 0; i < image.samples.size(); ++i) {
    const double albedo = (raster.albedo[3 * i] + raster.albedo[3 * i + 1] + raster.albedo[3 * i + 2]) / 3.0;
    // The window (and anything off the sheet) is paper until it is cut out; ink 0, paper 255.
    const double asPaper = albedo + (1.0 - raster.sheet[i] + raster.window[i]) * paper;
    const double level = (asPaper - ink) / (paper - ink);
    image.samples[i] = static_cast<std::uint16_t>(std::lround(std::clamp(level, 0.0, 1.0) * 255));
  }
  // The window's outline, one pixel wide, mid-grey: where to cut.
  const double xMin = (target.window.xMinMm - target.sheet.xMinMm) * pixelsPerMm;
  const double xMax = (target.window.xMaxMm - target.sheet.xMinMm) * pixelsPerMm;
  const double yMin = (target.sheet.yMaxMm - target.window.yMaxMm) * pixelsPerMm;
  const double yMax = (target.sheet.yMaxMm - target.window.yMinMm) * pixelsPerMm;
  const int left = static_cast<int>(std::floor(xMin)), right = static_cast<int>(std::ceil(xMax)) - 1;
  const int top = static_cast<int>(std::floor(yMin)), bottom = static_cast<int>(std::ceil(yMax)) - 1;
  for (int x = left; x <= right; ++x) {
    if ((x / 6) % 2 == 0) image.at(x, top, 0) = image.at(x, bottom, 0) = 128;
  }
  for (int yy = top; yy <= bottom; ++yy) {
    if ((yy / 6) % 2 == 0) image.at(left, yy, 0) = image.at(right, yy, 0) = 128;
  }
  return image;
}

void writeTargetPng(const std::filesystem::path& path, const vision::TargetGeometry& target,
                    double dpi) {
  writePng(path, renderTargetImage(target, dpi), dpi / 0.0254);
}

}  // namespace slicecap::io
