// `slicecap target`: the printable target (SVG, PDF or PNG at true scale) and its geometry JSON.
#include <filesystem>
#include <ostream>

#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/io/target_json.hpp"
#include "slicecap/io/target_print.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::cli {
namespace {

vision::TargetParams paramsOf(const ParsedArgs& args) {
  vision::TargetParams p;
  p.windowMm = args.number("window", p.windowMm);
  p.markerMm = args.number("marker", p.markerMm);
  p.bandMm = args.number("band", p.bandMm);
  p.markerGapMm = args.number("marker-gap", p.markerGapMm);
  p.marginMm = args.number("margin", p.marginMm);
  p.paperAlbedo = args.number("paper-albedo", p.paperAlbedo);
  p.inkAlbedo = args.number("ink-albedo", p.inkAlbedo);
  const double firstId = args.number("first-id", p.firstId);
  if (firstId != static_cast<int>(firstId)) throw UsageError("--first-id must be a whole number");
  p.firstId = static_cast<int>(firstId);
  std::string error;
  if (!p.isValid(&error)) throw UsageError("target: " + error);
  return p;
}

int run(const ParsedArgs& args, Streams& io) {
  const auto output = args.value("output");
  const auto json = args.value("json");
  if (!output && !json)
    throw UsageError("target: give -o TARGET.svg|.pdf|.png and/or --json TARGET.json");
  if (output && json) refuseClashingPaths({}, {{"-o", *output}, {"--json", *json}});
  const vision::TargetGeometry target = vision::buildTarget(paramsOf(args));
  const std::string paperName = args.value("paper").value_or("a4");
  if (paperName != "a4" && paperName != "letter") throw UsageError("--paper must be a4 or letter");
  const io::PaperSize paper = paperName == "a4" ? io::PaperSize::A4 : io::PaperSize::Letter;
  if (output) {
    const std::filesystem::path path = *output;
    const std::string extension = path.extension().string();
    if (extension == ".svg") {
      io::writeTargetSvg(path, target, paper);
    } else if (extension == ".pdf") {
      io::writeTargetPdf(path, target, paper);
    } else if (extension == ".png") {
      const double dpi = args.number("dpi", 300.0);
      if (dpi < 50.0 || dpi > 2400.0) throw UsageError("--dpi must be 50 to 2400");
      io::writeTargetPng(path, target, dpi);
    } else {
      throw UsageError("target: -o must end in .svg, .pdf or .png");
    }
    io.out << "wrote " << path.string() << ": " << target.name
           << ", print at 100 % (actual size)\n";
  }
  if (json) {
    io::writeTargetJson(*json, target);
    io.out << "wrote the geometry of " << target.name << " to " << *json << "\n";
  }
  return 0;
}

}  // namespace

Command targetCommand() {
  return {
      {"target",
       "-o TARGET.svg|.pdf|.png [--json TARGET.json] [--dpi N] [--window MM] [--marker MM] ...",
       "Write the printable target at true scale: a square window onto the material, a white\n"
       "reference band around it (four sides) with a black patch, and a ring of AprilTag tag36h11\n"
       "markers. SVG and PDF are an A4 (or letter) page with a 100 mm scale bar and instructions;\n"
       "PNG is the sheet alone at --dpi (stored in the file). Print at 100 %. --json writes the\n"
       "geometry (target frame in mm: origin at the window centre, x right, y up, z out of the\n"
       "material; every marker's id, size and corners in AprilTag order; window, patches, "
       "albedos).",
       {{"output", 'o', "FILE", "the printable target: .svg, .pdf or .png"},
        {"json", 0, "FILE", "the target's geometry as JSON"},
        {"dpi", 0, "N", "PNG resolution, dots per inch (default 300)"},
        {"paper", 0, "SIZE", "a4 (default) or letter, for SVG and PDF"},
        {"window", 0, "MM", "side of the square window (default 40)"},
        {"marker", 0, "MM", "tag size, black border square (default 16)"},
        {"band", 0, "MM", "width of the white reference band (default 12)"},
        {"marker-gap", 0, "MM", "least white between band and tags and between tags (default 4)"},
        {"margin", 0, "MM", "paper outside the tag ring (default 6)"},
        {"paper-albedo", 0, "A", "albedo of the paper, written to the JSON (default 0.85)"},
        {"ink-albedo", 0, "A", "albedo of the toner, written to the JSON (default 0.04)"},
        {"first-id", 0, "N", "id of the first tag (default 0)"}},
       0,
       0},
      run};
}

}  // namespace slicecap::cli
