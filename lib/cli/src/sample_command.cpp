// `slicecap sample`: a full table -> its ideal slices as CSV (the simulated acquisition).
#include <cmath>
#include <filesystem>
#include <ostream>

#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/recon/slice_extraction.hpp"
#include "slicecap/recon/uniform_sampling.hpp"

namespace slicecap::cli {
namespace {

// The uniform baseline's capture: N x N point samples at farthest-point grid directions.
int runUniform(const ParsedArgs& args, Streams& io) {
  for (const char* option : {"step", "diagonal-only", "lookup"}) {
    if (args.value(option) || args.flag(option))
      throw UsageError(std::string("sample: --uniform takes no --") + option);
  }
  const double count = *args.optionalNumber("uniform");
  if (count != std::floor(count) || count < 1 || count > bonn::kDirectionCount)
    throw UsageError("--uniform: the number of directions must be a whole number from 1 to 81");
  const std::filesystem::path output = args.required("output");
  refuseClashingPaths({{"the input", args.positional[0]}}, {{"-o", output}});
  const SliceSet samples =
      recon::extractUniformSamples(io::readTable(args.positional[0]), static_cast<int>(count));
  io::writeSliceCsv(output, samples);
  io.out << "wrote " << samples.sampleCount() << " point samples (" << count << " light x " << count
         << " view directions) to " << output.string() << "\n";
  return 0;
}

int run(const ParsedArgs& args, Streams& io) {
  if (args.value("uniform")) return runUniform(args, io);
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
  refuseClashingPaths({{"the input", args.positional[0]}}, {{"-o", output}});

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
           "TABLE -o SLICES.csv [--step DEG] [--diagonal-only] [--lookup linear|nearest] | "
           "TABLE -o SAMPLES.csv --uniform N",
           "Take the ideal slices of a full table (EXR or .f32), as a perfect capture would "
           "measure them.\n"
           "By default each slice has max(n(theta_i), n(theta_v)) samples (168 in all,\n"
           "docs/method.md section 2.2); --step 15 gives 24 a slice (192, as the real rig\n"
           "records). --uniform N takes the uniform baseline instead: N light x N view directions\n"
           "of the grid, spread by farthest-point selection from the pole (docs/method.md section\n"
           "6.3), as point samples (N = 13: the paper's 169); reconstruct them with --method\n"
           "uniform.",
           {{"output", 'o', "SLICES.csv", "where to write the slice CSV (required)"},
            {"step", 0, "DEG", "slice step in degrees (must divide 360)"},
            {"diagonal-only", 0, "", "only the four diagonal slices (isotropic capture)"},
            {"lookup", 0, "RULE", "linear (default) or nearest ring azimuth between grid points"},
            {"uniform", 0, "N", "N x N point samples of the uniform baseline instead of slices"}},
           1,
           1},
          run};
}

}  // namespace slicecap::cli
