// `slicecap eval`: every method on every material's simulated capture; per-material tables, means,
// report.csv/report.json and a PNG sheet per material.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <ostream>
#include <sstream>

#include "eval_materials.hpp"
#include "path_clash.hpp"
#include "slicecap/cli/command.hpp"
#include "slicecap/eval/report.hpp"
#include "slicecap/io/file_replacement.hpp"
#include "slicecap/io/io_error.hpp"
#include "slicecap/io/png_image.hpp"
#include "slicecap/methods/rbf_spec.hpp"
#include "slicecap/recon/slice_extraction.hpp"
#include "slicecap/recon/uniform_sampling.hpp"
#include "slicecap/render/sheets.hpp"

namespace slicecap::cli {
namespace {

using methods::Acquisition;
using methods::Method;
using methods::MethodOptions;
using methods::MethodRun;

std::vector<const Method*> parseMethods(const std::string& list) {
  std::vector<const Method*> methods;
  if (list == "all") {
    // eval's captures are ideal slices, which have no window cells: b-cells and prior-cells
    // would repeat b and prior.
    for (const Method& m : methods::reconstructionMethods())
      if (!methods::readsCellSamples(m.id)) methods.push_back(&m);
    return methods;
  }
  std::stringstream stream(list);
  std::string name;
  while (std::getline(stream, name, ',')) {
    const Method* method = &methods::findMethod(name);
    if (std::find(methods.begin(), methods.end(), method) != methods.end())
      throw UsageError("--methods: '" + name + "' is listed twice");
    methods.push_back(method);
  }
  if (methods.empty()) throw UsageError("--methods: no method named");
  return methods;
}

SliceSet simulateCapture(const Abrdf& table, Acquisition acquisition) {
  if (acquisition == Acquisition::UniformGrid13)
    return recon::extractUniformSamples(table, recon::kUniformBaselineDirections);
  return recon::extractSlices(table);
}

std::string formatRow(const std::string& label, const eval::Metrics& m, double milliseconds) {
  char line[160];
  std::snprintf(line, sizeof line, "  %-14s %7.2f %8.2f %8.2f %9.4f %6.3f %9.2f", label.c_str(),
                m.deltaE, m.rmse, m.psnrDb, m.relativeRmse, m.peakRatio, milliseconds);
  return line;
}

constexpr const char* kTableHeader =
    "  method              dE     RMSE  PSNR dB  rel.RMSE   peak        ms";

// Runs every method on one material; failures become rows with an error.
struct MaterialResult {
  std::vector<eval::EvaluationRow> rows;
  std::vector<MethodRun> runs;  // parallel to rows; empty table where the method failed
};

MaterialResult evaluateMaterial(const std::string& name, const Abrdf& truth,
                                const std::vector<const Method*>& methods,
                                const MethodOptions& options) {
  MaterialResult result;
  for (const Method* method : methods) {
    eval::EvaluationRow row{name, method->name, 0, {}, 0.0, {}};
    MethodRun run;
    try {
      const SliceSet samples = simulateCapture(truth, method->acquisition);
      row.samples = samples.sampleCount();
      const auto start = std::chrono::steady_clock::now();
      run = method->run(samples, options);
      row.milliseconds =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      row.metrics = eval::compare(truth, run.table);
    } catch (const std::exception& e) {
      row.error = e.what();
    }
    result.rows.push_back(row);
    result.runs.push_back(std::move(run));
  }
  return result;
}

void writeSheet(const std::filesystem::path& path, const MaterialSource& material,
                const Abrdf& truth, const MaterialResult& result) {
  std::vector<render::SheetPanel> panels;
  char line[128];
  for (std::size_t k = 0; k < result.rows.size(); ++k) {
    const eval::EvaluationRow& row = result.rows[k];
    if (!row.error.empty()) continue;
    render::SheetPanel panel{
        row.method + " (" + result.runs[k].exrMethodName + ")", &result.runs[k].table, {}};
    std::snprintf(line, sizeof line, "dE %.2f  RMSE %.2f", row.metrics.deltaE, row.metrics.rmse);
    panel.lines.push_back(line);
    std::snprintf(line, sizeof line, "PSNR %.2f dB  rel %.3f  peak %.2f", row.metrics.psnrDb,
                  row.metrics.relativeRmse, row.metrics.peakRatio);
    panel.lines.push_back(line);
    std::snprintf(line, sizeof line, "%zu samples, %.1f ms", row.samples, row.milliseconds);
    panel.lines.push_back(line);
    panels.push_back(std::move(panel));
  }
  std::snprintf(line, sizeof line, "max f cos = %.4g 1/sr", eval::cosWeightedMaximum(truth));
  const render::Canvas sheet = render::evaluationSheet(
      material.name, truth, {material.origin, line, "cos-weighted, sRGB, x255"}, panels);
  io::writePng(path, sheet.toPng());
}

void printSummary(std::ostream& out, const std::vector<eval::MethodSummary>& summaries,
                  std::size_t materialCount) {
  out << "\nmeans over " << materialCount << " materials (means of per-material values)\n"
      << kTableHeader << "\n";
  const eval::MethodSummary* uniform = nullptr;
  for (const eval::MethodSummary& s : summaries) {
    out << formatRow(s.method, s.mean, s.meanMilliseconds)
        << (s.failures ? "  (" + std::to_string(s.failures) + " failed)" : "") << "\n";
    if (s.method == methods::cliName(methods::MethodId::Uniform)) uniform = &s;
  }
  if (uniform && uniform->materials > 0 && summaries.size() > 1) {
    out << "\nmargin over the uniform baseline (positive = better than uniform)\n"
        << "  method              dE     RMSE  PSNR dB\n";
    char line[128];
    for (const eval::MethodSummary& s : summaries) {
      if (&s == uniform || s.materials == 0) continue;
      std::snprintf(line, sizeof line, "  %-14s %+7.2f %+8.2f %+8.2f\n", s.method.c_str(),
                    uniform->mean.deltaE - s.mean.deltaE, uniform->mean.rmse - s.mean.rmse,
                    s.mean.psnrDb - uniform->mean.psnrDb);
      out << line;
    }
  }
  for (const eval::MethodSummary& s : summaries) {
    out << "\nworst " << s.worst.size() << " by dE, " << s.method << ":";
    for (const eval::EvaluationRow& w : s.worst) {
      char entry[160];
      std::snprintf(entry, sizeof entry, "\n  %-44s dE %.2f  RMSE %.2f  PSNR %.2f",
                    w.material.c_str(), w.metrics.deltaE, w.metrics.rmse, w.metrics.psnrDb);
      out << entry;
    }
    out << "\n";
  }
}

// Where the run's results go, as the options say.
struct EvalOutputs {
  bool json = false, quiet = false, sheets = false;
  std::optional<std::filesystem::path> out;
  // report.csv is written row by row into a temporary beside it that replaces it only when the
  // run ends: an eval stopped half-way leaves the previous report as it was.
  std::optional<io::ReplacementFile> csvFile;
  std::ofstream csv;
};

// The rows so far, and how many materials or methods failed.
struct EvalTally {
  std::vector<eval::EvaluationRow> rows;
  int failures = 0;
};

// --out may not be (or hold the reports over) an input table; then report.csv's temporary is
// opened and its header written. Throws UsageError on a clash, io::IoError naming report.csv.
void prepareOutDirectory(const std::vector<MaterialSource>& materials, EvalOutputs& outputs) {
  const std::filesystem::path& out = *outputs.out;
  std::vector<NamedPath> tables;
  for (const MaterialSource& material : materials)
    if (std::filesystem::exists(material.origin))  // a file, not a built-in material
      tables.push_back({"the input", material.origin});
  refuseClashingPaths(
      tables, {{"--out", out}, {"--out", out / "report.csv"}, {"--out", out / "report.json"}});
  std::filesystem::create_directories(out);
  outputs.csvFile.emplace(out / "report.csv");
  outputs.csv.open(outputs.csvFile->writePath(), std::ios::binary | std::ios::trunc);
  if (!outputs.csv) throw io::IoError((out / "report.csv").string() + ": cannot create report");
  eval::writeReportCsvHeader(outputs.csv);
}

// One method's row to the table, stderr (a failure) and report.csv; returns its progress entry.
std::string reportRow(const std::string& materialName, const eval::EvaluationRow& row,
                      EvalOutputs& outputs, Streams& io, EvalTally& tally) {
  std::string progress;
  if (!row.error.empty()) {
    ++tally.failures;
    io.err << "slicecap eval: " << materialName << ", method " << row.method << ": "
           << row.error << "\n";
    progress = " " + row.method + " failed";
  } else {
    char entry[64];
    std::snprintf(entry, sizeof entry, " %s %.2f", row.method.c_str(), row.metrics.deltaE);
    progress = entry;
  }
  if (!outputs.json) {
    io.out << (row.error.empty() ? formatRow(row.method, row.metrics, row.milliseconds)
                                 : "  " + row.method + "  failed: " + row.error)
           << "\n";
  }
  if (outputs.csv.is_open()) eval::writeReportCsvRow(outputs.csv, row);
  tally.rows.push_back(row);
  return progress;
}

// Every method on one material, reported as it ends; returns the material's progress line.
std::string evaluateAndReport(const MaterialSource& material, const std::string& progressLabel,
                              const std::vector<const Method*>& methods,
                              const MethodOptions& options, EvalOutputs& outputs, Streams& io,
                              EvalTally& tally) {
  std::string progress = progressLabel;
  try {
    const Abrdf truth = material.load();
    const MaterialResult result = evaluateMaterial(material.name, truth, methods, options);
    if (!outputs.json)
      io.out << material.name << "  (" << material.origin << ")\n" << kTableHeader << "\n";
    for (const eval::EvaluationRow& row : result.rows)
      progress += reportRow(material.name, row, outputs, io, tally);
    if (outputs.csv.is_open()) outputs.csv.flush();
    if (outputs.sheets)
      writeSheet(*outputs.out / (material.name + ".png"), material, truth, result);
  } catch (const std::exception& e) {
    // A bad table costs its own row, never the materials already evaluated.
    ++tally.failures;
    io.err << "slicecap eval: " << material.origin << ": " << e.what() << "\n";
    progress += " failed";
  }
  return progress;
}

// report.json, then report.csv's temporary in place of the old report.
void finishReportFiles(const nlohmann::json& report, EvalOutputs& outputs) {
  const std::filesystem::path& out = *outputs.out;
  io::writeStreamReplacing(out / "report.json",
                           [&](std::ostream& file) { file << report.dump(2) << "\n"; });
  outputs.csv.close();  // flushes: a full disk shows here at the latest
  if (!outputs.csv) throw io::IoError((out / "report.csv").string() + ": write failed");
  outputs.csvFile->commit();
}

int run(const ParsedArgs& args, Streams& io) {
  const std::vector<const Method*> methods =
      parseMethods(args.value("methods").value_or("b,a,uniform"));
  MethodOptions options;
  if (const std::optional<std::string> spec = args.value("rbf"))
    methods::applyRbfSpec(*spec, options);
  const std::vector<MaterialSource> materials = resolveMaterials(args.positional);
  EvalOutputs outputs;
  outputs.json = args.flag("json");
  outputs.quiet = args.flag("quiet");
  outputs.out = args.value("out");
  outputs.sheets = outputs.out && !args.flag("no-sheets");
  if (outputs.out) prepareOutDirectory(materials, outputs);

  EvalTally tally;
  std::vector<std::string> methodNames;
  for (const Method* m : methods)
    methodNames.push_back(m->name);
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const std::string label = "eval " + std::to_string(i + 1) + "/" +
                              std::to_string(materials.size()) + " " + materials[i].name + ":";
    const std::string progress =
        evaluateAndReport(materials[i], label, methods, options, outputs, io, tally);
    if (!outputs.quiet) io.err << progress << " (dE)\n";
  }
  const std::vector<eval::MethodSummary> summaries = eval::summarise(tally.rows, methodNames);
  const nlohmann::json report = eval::reportJson(tally.rows, summaries);
  if (outputs.out) finishReportFiles(report, outputs);
  if (outputs.json) {
    io.out << report.dump(2) << "\n";
  } else {
    printSummary(io.out, summaries, materials.size());
  }
  if (!outputs.quiet) {
    io.err << "eval: " << materials.size() << " materials x " << methods.size() << " methods in "
           << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
           << " s"
           << (outputs.out ? "; wrote " + outputs.out->string() : std::string()) << "\n";
  }
  return tally.failures ? 1 : 0;
}

}  // namespace

Command evalCommand() {
  std::string description =
      "Evaluate reconstruction methods on materials with known truth: for each material, "
      "simulate\n"
      "each method's capture (ideal slices, 168 samples; uniform: 13 x 13 point samples), "
      "reconstruct,\n"
      "and compare with the paper's metrics (dE, RMSE, PSNR, as `compare`), the linear "
      "relative RMSE\n"
      "and the peak ratio (the reconstruction's largest value over the truth's).\n"
      "Prints a table per material, the means (of per-material values), the margin over "
      "the uniform\n"
      "baseline and the worst five materials per method; progress goes to stderr.\n"
      "MATERIALS: table files (.exr, .f32), folders of them, built-in material names, or\n"
      "builtin:anisotropic, builtin:isotropic, builtin:all.\n"
      "With --out DIR: DIR/report.csv (one row per material and method, written as it goes),\n"
      "DIR/report.json (rows and means) and DIR/MATERIAL.png per material: the reference, each\n"
      "reconstruction and its x10 difference in the paper's 81 x 81 layout, numbers under each.\n"
      "A material or method that fails is reported on stderr and the run goes on; exit code 1 "
      "then.\n\nmethods:\n";
  description += methods::methodHelpLines();
  return {
      {"eval",
       "MATERIALS... [--methods b,a,uniform|all] [--rbf SPEC] [--out DIR] [--no-sheets] [--json] "
       "[--quiet]",
       description,
       {{"methods", 0, "LIST", "comma-separated method names, or all (default b,a,uniform)"},
        {"rbf", 0, "SPEC",
         "a and uniform (same machinery): key=value,... of kernel=mq|imq|r|r3, "
         "poly=const|linear, r0=SCALE (x median NN distance), frame=relative|absolute, "
         "gamma=G (interpolate v^(1/G))"},
        {"out", 'o', "DIR", "write report.csv, report.json and a PNG sheet per material"},
        {"no-sheets", 0, "", "with --out: skip the PNG sheets"},
        {"json", 0, "", "print the JSON report instead of the tables"},
        {"quiet", 'q', "", "no progress on stderr"}},
       1,
       1 << 20},
      run};
}

}  // namespace slicecap::cli
