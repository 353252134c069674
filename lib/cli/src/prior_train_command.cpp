// `slicecap prior-train`: the prior file from a folder of measured tables (regenerates
// data/prior/prior.bin).
#include <algorithm>
#include <filesystem>
#include <ostream>

#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/cli/command_error.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/prior/prior_model.hpp"

namespace slicecap::cli {
namespace {

int run(const ParsedArgs& args, Streams& io) {
  prior::TrainingParams params;
  params.components = static_cast<int>(args.number("components", params.components));
  std::string error;
  if (!params.isValid(&error)) throw UsageError("prior-train: " + error);
  const std::filesystem::path folder = args.positional[0];
  const std::string prefix = args.value("prefix").value_or("");
  if (!std::filesystem::is_directory(folder))
    throw CommandError(folder.string() + ": not a folder");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".f32" && name.rfind(prefix, 0) == 0)
      files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw CommandError(folder.string() + ": no .f32 tables" +
                       (prefix.empty() ? "" : " starting with '" + prefix + "'"));
  const std::filesystem::path output = args.required("output");
  std::vector<NamedPath> inputs;
  for (const auto& f : files)
    inputs.push_back({"the input table", f});
  refuseClashingPaths(inputs, {{"-o", output}});
  std::vector<Abrdf> tables;
  std::string names;
  for (const auto& f : files) {
    tables.push_back(io::readTable(f));
    names += " " + f.stem().string();
  }
  const std::string provenance =
      "slicecap prior: PCA (" + std::to_string(params.components) +
      " components) of log(f cos_i cos_v + 0.01 max) of " + std::to_string(tables.size()) +
      " tables of " + folder.filename().string() +
      " (Sztrajman et al. 2021 neural fits of MERL, RGL and Nielsen et al. measurements, MIT "
      "licence, see data/prior/LICENSE.Neural-BRDF); command: slicecap prior-train; tables:" +
      names;
  const prior::PriorModel model = prior::trainPriorModel(tables, params, provenance);
  prior::writePriorModel(output, model);
  io.out << "wrote a prior of " << model.components() << " components from " << tables.size()
         << " tables to " << output.string() << "\n";
  return 0;
}

}  // namespace

Command priorTrainCommand() {
  return {{"prior-train",
           "FOLDER -o PRIOR.bin [--components N] [--prefix TEXT]",
           "Train the reconstruction prior of `--method prior` from a folder of .f32 tables (e.g.\n"
           "$SLICECAP_SHARED_DATA/nbrdf-bonn81, not part of slicecap): PCA of log(f cos_i cos_v +\n"
           "0.01 max) over every channel of every table. scripts/prior-train regenerates the\n"
           "shipped data/prior/prior.bin this way.",
           {{"output", 'o', "PRIOR.bin", "where to write the prior (required)"},
            {"components", 0, "N", "number of components kept (default 16)"},
            {"prefix", 0, "TEXT", "only tables whose file name starts with TEXT (e.g. merl_)"}},
           1,
           1},
          run};
}

}  // namespace slicecap::cli
