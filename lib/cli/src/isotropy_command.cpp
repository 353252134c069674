// `slicecap isotropy`: are the axial sweeps needed? The isotropy test on a slice CSV.
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/io/slice_csv.hpp"
#include "slicecap/prior/isotropy_test.hpp"
#include "slicecap/prior/prior_location.hpp"

namespace slicecap::cli {
namespace {

int run(const ParsedArgs& args, Streams& io) {
  prior::IsotropyParams params;
  params.diagonalThreshold = args.number("diagonal-threshold", params.diagonalThreshold);
  params.axialThreshold = args.number("axial-threshold", params.axialThreshold);
  params.priorScoreRatio = args.number("prior-ratio", params.priorScoreRatio);
  std::string error;
  if (!params.isValid(&error)) throw UsageError("isotropy: " + error);
  const SliceSet slices = io::readSliceCsv(args.positional[0]);
  const prior::IsotropyVerdict verdict =
      prior::testIsotropy(slices, prior::defaultPriorModel(), params);
  if (args.flag("json")) {
    nlohmann::json j{{"input", args.positional[0]},
                     {"isotropic", verdict.isotropic},
                     {"axial_sweeps_needed", !verdict.isotropic},
                     {"diagonal_score", verdict.diagonalScore},
                     {"axial_score", verdict.axialScore},
                     {"prior_gcv_ratio", verdict.priorScoreRatio},
                     {"informative", verdict.informative},
                     {"reason", verdict.reason}};
    for (const prior::SliceIsotropyScore& s : verdict.slices)
      j["slices"].push_back({{"slice", toString(s.slice)}, {"score", s.score}});
    io.out << j.dump(2) << "\n";
  } else {
    for (const prior::SliceIsotropyScore& s : verdict.slices)
      io.out << "  " << toString(s.slice) << ": " << std::fixed << std::setprecision(3) << s.score
             << "\n";
    io.out << (!verdict.isotropic    ? "anisotropic: measure the axial sweeps\n"
               : verdict.informative ? "isotropic: the axial sweeps are not needed\n"
                                     : "cannot tell: measure the axial sweeps to be sure\n")
           << verdict.reason << "\n";
  }
  // Exit 0 either way: the verdict is a result, not a failure; scripts read --json or the line.
  return 0;
}

}  // namespace

Command isotropyCommand() {
  return {
      {"isotropy",
       "SLICES.csv [--json] [--prior-ratio X] [--diagonal-threshold X] [--axial-threshold X]",
       "Say whether a material looks isotropic from its slices, i.e. whether the axial sweeps "
       "are needed\n"
       "after the diagonal ones. The slices are fitted with the learned prior at their actual "
       "angles, with and\n"
       "without half-vector anisotropy terms: anisotropic when the terms cut the fit's GCV score "
       "below\n"
       "--prior-ratio of the isotropic fit's. Also scored: each axial slice's RMS log spread "
       "(constant when\n"
       "isotropic) and each diagonal slice's RMS log asymmetry (half-turn and, at mixed "
       "elevations, mirror).\n"
       "Only equal-elevation diagonal slices (30/30, 75/75) cannot show anisotropy: the answer "
       "is then\n"
       "\"cannot tell\". Exit 0 whatever the verdict.",
       {{"json", 0, "", "print JSON instead of text"},
        {"prior-ratio", 0, "X", "largest GCV ratio that means anisotropic (default 0.3)"},
        {"diagonal-threshold", 0, "X", "largest isotropic diagonal asymmetry (default 2.0)"},
        {"axial-threshold", 0, "X", "largest isotropic axial spread (default 0.2)"}},
       1,
       1},
      run};
}

}  // namespace slicecap::cli
