// `slicecap compare`: the paper's metrics of a table against a reference.
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>

#include "slicecap/cli/command.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/io/table_file.hpp"

namespace slicecap::cli {
namespace {

int run(const ParsedArgs& args, Streams& io) {
  const Abrdf reference = io::readTable(args.positional[0]);
  const Abrdf test = io::readTable(args.positional[1]);
  const eval::Metrics m = eval::compare(reference, test);
  if (args.flag("json")) {
    io.out << nlohmann::json{{"reference", args.positional[0]},
                             {"test", args.positional[1]},
                             {"delta_e", m.deltaE},
                             {"rmse", m.rmse},
                             {"psnr_db", m.psnrDb},
                             {"relative_rmse", m.relativeRmse},
                             {"peak_ratio", m.peakRatio}}
                  .dump(2)
           << "\n";
  } else {
    io.out << std::fixed << std::setprecision(2) << "dE " << m.deltaE << "  RMSE " << m.rmse
           << "  PSNR " << m.psnrDb << " dB  linear relative RMSE " << std::setprecision(4)
           << m.relativeRmse << "  peak ratio " << m.peakRatio << "\n";
  }
  return 0;
}

}  // namespace

Command compareCommand() {
  return {
      {"compare",
       "REFERENCE TEST [--json]",
       "Compare two 81 x 81 tables (EXR or .f32) in the paper's convention: both times "
       "cos(theta_i),\n"
       "divided by the reference's maximum, sRGB-encoded to 8 bits; mean CIE76 dE, RMSE and PSNR\n"
       "(20 log10(255 / RMSE), at most 100 dB); plus the linear-domain relative RMSE\n"
       "||TEST - REFERENCE|| / ||REFERENCE|| over all 19683 BRDF values, and the peak ratio\n"
       "max(TEST) / max(REFERENCE) (a clipped highlight: << 1).",
       {{"json", 0, "", "print JSON instead of text"}},
       2,
       2},
      run};
}

}  // namespace slicecap::cli
