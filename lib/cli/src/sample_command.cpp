// `slicecap sample`: a full table -> its ideal slices as CSV (the simulated acquisition).
#include <filesystem>
#include <ostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::cli {
namespace {

int run(const ParsedArgs& args, Streams& io) {
  recon::ExtractionParams params;
  params.stepDeg = args.optionalNumber("step");
  params.diagonalOnly = args.flag("diagonal-only");
  const std::string lookup = args.value("lookup").value_or("linear");
  if (lookup == "nearest") {
    params.lookup = recon::AzimuthLookup::Nearest;
  } else if (lookup != "linear") {
    throw UsageError("--lookup: '" + lookup + "' is not one of linear, nearest");
  }
  std::string error;
  if (!params.isValid(&error)) throw UsageError("--step: " + error);
  const std::filesystem::path output = args.required("output");

  const Abrdf table = io::readTable(args.positional[0]);
  const SliceSet slices = recon::extractSlices(table, params);
  io::writeSliceCsv(output, slices);
  io.out << "wrote " << slices.sampleCount() << " samples in " << slices.slices().size()
         << " slices to " << output.string() << "\n";
  return 0;
}

}  // namespace

Command sampleCommand() {
  return {{"sample",
           "TABLE -o SLICES.csv [--step DEG] [--diagonal-only] [--lookup linear|nearest]",
           "Take the ideal slices of a full table (EXR or .f32), as a perfect capture would "
           "measure them.\n"
           "By default each slice has max(n(theta_i), n(theta_v)) samples (168 in all, METHOD.md "
           "2.2);\n"
           "--step 15 gives 24 a slice (192, as the real rig records).",
           {{"output", 'o', "SLICES.csv", "where to write the slice CSV (required)"},
            {"step", 0, "DEG", "slice step in degrees (must divide 360)"},
            {"diagonal-only", 0, "", "only the four diagonal slices (isotropic capture)"},
            {"lookup", 0, "RULE", "linear (default) or nearest ring azimuth between grid points"}},
           1,
           1},
          run};
}

}  // namespace slicecap::cli
