// `slicecap isotropy`: are the axial sweeps needed? The isotropy test on a slice CSV.
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/prior/isotropy_test.hpp"

namespace slicecap::cli {
namespace {

int run(const ParsedArgs& args, Streams& io) {
  prior::IsotropyParams params;
  params.diagonalThreshold = args.number("diagonal-threshold", params.diagonalThreshold);
  params.axialThreshold = args.number("axial-threshold", params.axialThreshold);
  std::string error;
  if (!params.isValid(&error)) throw UsageError("isotropy: " + error);
  const SliceSet slices = io::readSliceCsv(args.positional[0]);
  const prior::IsotropyVerdict verdict = prior::testIsotropy(slices, params);
  if (args.flag("json")) {
    nlohmann::json j{{"input", args.positional[0]},
                     {"isotropic", verdict.isotropic},
                     {"axial_sweeps_needed", !verdict.isotropic},
                     {"diagonal_score", verdict.diagonalScore},
                     {"axial_score", verdict.axialScore},
                     {"reason", verdict.reason}};
    for (const prior::SliceIsotropyScore& s : verdict.slices)
      j["slices"].push_back({{"slice", toString(s.slice)}, {"score", s.score}});
    io.out << j.dump(2) << "\n";
  } else {
    for (const prior::SliceIsotropyScore& s : verdict.slices)
      io.out << "  " << toString(s.slice) << ": " << std::fixed << std::setprecision(3) << s.score
             << "\n";
    io.out << (verdict.isotropic ? "isotropic: the axial sweeps are not needed\n"
                                 : "anisotropic: measure the axial sweeps\n")
           << verdict.reason << "\n";
  }
  // Exit 0 either way: the verdict is a result, not a failure; scripts read --json or the line.
  return 0;
}

}  // namespace

Command isotropyCommand() {
  return {
      {"isotropy",
       "SLICES.csv [--json] [--diagonal-threshold X] [--axial-threshold X]",
       "Say whether a material looks isotropic from its slices, i.e. whether the axial sweeps "
       "are needed.\n"
       "An isotropic material's diagonal slice is half-turn periodic (x, x + 180) and, at "
       "mixed elevations,\n"
       "mirror symmetric (x, -x); its axial slice is constant. Each slice is scored by the RMS "
       "of log\n"
       "differences (values below 1 % of the largest cos-weighted sample are raised to it); "
       "above the\n"
       "threshold means anisotropic. Diagonal sweeps cannot see a grain that runs along phi = 0 "
       "or 90 deg.",
       {{"json", 0, "", "print JSON instead of text"},
        {"diagonal-threshold", 0, "X", "largest isotropic diagonal score (default 0.15)"},
        {"axial-threshold", 0, "X", "largest isotropic axial score (default 0.15)"}},
       1,
       1},
      run};
}

}  // namespace slicecap::cli
