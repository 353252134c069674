// The evaluation of issue 10: the learned prior against Method B in the same run, on held-out
// measured tables (basis from MERL, tested on RGL + Nielsen), 5-fold cross-validation over all
// 159, fewer sweeps, the anisotropic analytic materials, capture noise, and the isotropy test's
// error rates. Usage: prior_eval [TABLES_DIR] [--per-material] [--isotropy-only]
// (scripts/prior-eval)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "slicecap/core/grid_interpolation.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/io/table_file.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/prior/isotropy_test.hpp"
#include "slicecap/prior/prior_location.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/method_b.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace {

using namespace slicecap;

struct Material {
  std::string name;
  Abrdf table;
};

// A capture: which sweeps, and whether it is ideal or has the noise (2 % multiplicative,
// +-3 deg uniform jitter of all four angles, 10 % of samples missing).
enum class Sweeps { All8, Diagonal4, Diagonal2 };
const char* sweepName(Sweeps s) {
  return s == Sweeps::All8 ? "8 sweeps" : s == Sweeps::Diagonal4 ? "4 diagonal" : "2 diagonal";
}

SliceSet capture(const Abrdf& table, Sweeps sweeps, bool noisy, unsigned seed) {
  recon::ExtractionParams params;
  params.diagonalOnly = sweeps != Sweeps::All8;
  const SliceSet ideal = recon::extractSlices(table, params);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-3.0, 3.0), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  SliceSet out;
  for (const Slice& slice : ideal.slices()) {
    if (sweeps == Sweeps::Diagonal2 &&
        slice.id.elevations.thetaIDeg != slice.id.elevations.thetaVDeg)
      continue;
    for (SliceSample s : slice.samples) {
      if (noisy) {
        if (unit(rng) < 0.10) continue;
        s.light = {std::max(0.0, s.light.thetaDeg + jitter(rng)), s.light.phiDeg + jitter(rng)};
        s.view = {std::max(0.0, s.view.thetaDeg + jitter(rng)), s.view.phiDeg + jitter(rng)};
        s.value = evaluate(table, s.light, s.view);
        for (std::size_t c = 0; c < 3; ++c)
          s.value[c] *= 1.0 + noise(rng);
      }
      out.add(slice.id, s);
    }
  }
  return out;
}

struct Scores {
  std::vector<double> priorDe, bDe, prior8, b8;
  eval::Metrics priorSum{}, bSum{};
};

void add(eval::Metrics& sum, const eval::Metrics& m) {
  sum.deltaE += m.deltaE;
  sum.rmse += m.rmse;
  sum.psnrDb += m.psnrDb;
  sum.relativeRmse += m.relativeRmse;
}

// Runs one condition over materials; B is run on the same capture (isotropic B for diagonal
// sweeps; none for 2 sweeps, which B cannot use) and on the ideal 8 sweeps for the goal's
// comparison. Prints means and the count of materials where the prior is > 10 % worse than B.
void runCondition(const std::string& label, const std::vector<const Material*>& materials,
                  const std::function<const prior::PriorModel&(const Material&)>& priorFor,
                  Sweeps sweeps, bool noisy, bool perMaterial) {
  eval::Metrics p{}, b{}, b8{};
  int worse = 0, worseThanB8 = 0, anisotropyUsed = 0, blended = 0;
  const double n = double(materials.size());
  std::string worst;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const Material& m = *materials[i];
    const unsigned seed = 1000u + unsigned(i) * 7919u;
    const SliceSet slices = capture(m.table, sweeps, noisy, seed);
    prior::PriorReport report;
    const eval::Metrics mp =
        eval::compare(m.table, prior::reconstructWithPrior(slices, priorFor(m), {}, &report));
    anisotropyUsed += report.anisotropyTermsUsed;
    blended += report.methodBBlended;
    const eval::Metrics mb8 = eval::compare(
        m.table, recon::reconstructMethodB(capture(m.table, Sweeps::All8, noisy, seed)));
    eval::Metrics mb = mb8;
    if (sweeps == Sweeps::Diagonal4) {
      recon::MethodBParams iso;
      iso.isotropic = true;
      mb = eval::compare(m.table, recon::reconstructMethodB(slices, iso));
    }
    add(p, mp);
    add(b, mb);
    add(b8, mb8);
    if (sweeps != Sweeps::Diagonal2 && mp.deltaE > 1.1 * mb.deltaE) {
      ++worse;
      char line[160];
      std::snprintf(line, sizeof line, "      worse than B: %-44s prior %.2f  B %.2f\n",
                    m.name.c_str(), mp.deltaE, mb.deltaE);
      worst += line;
    }
    if (mp.deltaE > 1.1 * mb8.deltaE) ++worseThanB8;
    if (perMaterial)
      std::printf(
          "    %-46s prior %6.2f  B %6.2f  B(8) %6.2f  fit %.3f gcv %.4f range %.2f w %.2f%s\n",
          m.name.c_str(), mp.deltaE, mb.deltaE, mb8.deltaE, report.fitRmsLog, report.isotropicScore,
          report.dynamicRangeLog, report.priorWeight,
          report.anisotropyTermsUsed ? "  [aniso]" : "");
  }
  std::printf("  %-34s %-10s %-5s prior dE %5.2f RMSE %5.2f PSNR %5.2f rel %5.3f | ", label.c_str(),
              sweepName(sweeps), noisy ? "noisy" : "ideal", p.deltaE / n, p.rmse / n, p.psnrDb / n,
              p.relativeRmse / n);
  if (sweeps == Sweeps::Diagonal2)
    std::printf("B n/a          ");
  else
    std::printf("B dE %5.2f RMSE %5.2f PSNR %5.2f rel %5.3f ", b.deltaE / n, b.rmse / n,
                b.psnrDb / n, b.relativeRmse / n);
  std::printf(
      "| B(8) dE %5.2f | >10%% worse: %d vs B, %d vs B(8) | aniso terms %d/%zu | B blended %d\n",
      b8.deltaE / n, worse, worseThanB8, anisotropyUsed, materials.size(), blended);
  std::fputs(worst.c_str(), stdout);
  std::fflush(stdout);
}

std::vector<Material> loadShared(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() == ".f32") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<Material> out;
  for (const auto& f : files)
    out.push_back({f.stem().string(), io::readTable(f)});
  return out;
}

prior::PriorModel train(const std::vector<const Material*>& set) {
  std::vector<Abrdf> tables;
  for (const Material* m : set)
    tables.push_back(m->table);
  return prior::trainPriorModel(tables);
}

// The isotropy test with the prior that has not seen the material (priorFor).
void isotropyRates(const std::string& label, const std::vector<const Material*>& materials,
                   const std::function<const prior::PriorModel&(const Material&)>& priorFor,
                   Sweeps sweeps, bool noisy, bool expectIsotropic) {
  int wrong = 0;
  std::string names;
  std::vector<double> diagonal, axial, ratio;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const SliceSet slices =
        capture(materials[i]->table, sweeps, noisy, 1000u + unsigned(i) * 7919u);
    const prior::IsotropyVerdict v = prior::testIsotropy(slices, priorFor(*materials[i]));
    ratio.push_back(v.priorScoreRatio);
    diagonal.push_back(v.diagonalScore);
    axial.push_back(v.axialScore);
    if (v.isotropic != expectIsotropic) {
      ++wrong;
      names += " " + materials[i]->name;
    }
  }
  std::printf("  %-28s %-10s %-5s called %s: %d of %zu%s%s\n", label.c_str(), sweepName(sweeps),
              noisy ? "noisy" : "ideal", expectIsotropic ? "anisotropic" : "isotropic", wrong,
              materials.size(), wrong ? ":" : "", wrong && wrong < 12 ? names.c_str() : "");
  // Score quantiles (min, 5 %, median, 95 %, max): where the thresholds sit between the sets.
  for (auto* scores : {&ratio, &diagonal, &axial}) {
    std::sort(scores->begin(), scores->end());
    auto at = [&](double q) { return (*scores)[std::size_t(q * double(scores->size() - 1))]; };
    std::printf("      %s scores: %.3f %.3f %.3f %.3f %.3f\n",
                scores == &ratio      ? "GCV ratio"
                : scores == &diagonal ? "diagonal "
                                      : "axial    ",
                at(0), at(0.05), at(0.5), at(0.95), at(1));
  }
}

// 5-fold priors of a set (fold = index mod 5 of the sorted names): each table's prior never saw it.
struct FoldPriors {
  std::vector<const Material*> set;
  std::vector<prior::PriorModel> folds;
  explicit FoldPriors(const std::vector<const Material*>& materials) : set(materials) {
    for (int f = 0; f < 5; ++f) {
      std::vector<const Material*> training;
      for (std::size_t i = 0; i < set.size(); ++i) {
        if (int(i % 5) != f) training.push_back(set[i]);
      }
      folds.push_back(train(training));
    }
  }
  std::function<const prior::PriorModel&(const Material&)> lookup() const {
    return [this](const Material& m) -> const prior::PriorModel& {
      const auto it = std::find(set.begin(), set.end(), &m);
      return folds[std::size_t(it - set.begin()) % 5];
    };
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path dir = "../shared/data/nbrdf-bonn81";
  bool perMaterial = false, isotropyOnly = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--per-material")
      perMaterial = true;
    else if (a == "--isotropy-only")
      isotropyOnly = true;
    else
      dir = a;
  }
  std::vector<Material> analytic;
  for (const models::NamedMaterial& m : models::anisotropicMaterials())
    analytic.push_back({m.name, models::tabulate(*m.model)});
  std::vector<const Material*> anisotropic;
  for (const Material& m : analytic)
    anisotropic.push_back(&m);

  if (!std::filesystem::is_directory(dir)) {
    std::printf("%s is absent: only the anisotropic materials, with the shipped prior\n",
                dir.string().c_str());
    const prior::PriorModel& shipped = prior::defaultPriorModel();
    for (bool noisy : {false, true})
      runCondition(
          "anisotropic analytic (shipped prior)", anisotropic,
          [&](const Material&) -> const prior::PriorModel& { return shipped; }, Sweeps::All8, noisy,
          perMaterial);
    return 0;
  }
  const std::vector<Material> shared = loadShared(dir);
  std::vector<const Material*> merl, heldOut, all;
  for (const Material& m : shared) {
    (m.name.rfind("merl", 0) == 0 ? merl : heldOut).push_back(&m);
    all.push_back(&m);
  }
  std::printf("%zu tables (%zu MERL, %zu RGL + Nielsen)\n", shared.size(), merl.size(),
              heldOut.size());

  if (!isotropyOnly) {
    std::printf("\nheld-out: prior trained on MERL only, tested on RGL + Nielsen\n");
    const prior::PriorModel merlPrior = train(merl);
    auto fromMerl = [&](const Material&) -> const prior::PriorModel& { return merlPrior; };
    for (bool noisy : {false, true}) {
      for (Sweeps s : {Sweeps::All8, Sweeps::Diagonal4, Sweeps::Diagonal2})
        runCondition("held-out RGL+Nielsen", heldOut, fromMerl, s, noisy, perMaterial);
    }

    // 5-fold cross-validation (fold = index mod 5 of the sorted names): each table is
    // reconstructed with the prior trained on the other four folds.
    auto crossValidate = [&](const std::string& label, const std::vector<const Material*>& set) {
      const FoldPriors folds(set);
      for (bool noisy : {false, true}) {
        for (Sweeps s : {Sweeps::All8, Sweeps::Diagonal4, Sweeps::Diagonal2})
          runCondition(label, set, folds.lookup(), s, noisy, perMaterial);
      }
    };
    std::printf(
        "\n5-fold cross-validation within the 100 MERL tables (where parameters are tuned)\n");
    crossValidate("5-fold CV, MERL only", merl);
    std::printf("\n5-fold cross-validation over all %zu tables\n", all.size());
    crossValidate("5-fold CV, all 159", all);

    std::printf("\nanisotropic analytic materials (prior trained on all 159 tables)\n");
    const prior::PriorModel allPrior = train(all);
    for (bool noisy : {false, true}) {
      for (Sweeps s : {Sweeps::All8, Sweeps::Diagonal4})
        runCondition(
            "anisotropic analytic", anisotropic,
            [&](const Material&) -> const prior::PriorModel& { return allPrior; }, s, noisy, true);
    }
  }

  std::printf(
      "\nisotropy test error rates (thresholds set on MERL; MERL: 5-fold priors within "
      "MERL; others: the MERL prior)\n");
  const FoldPriors merlFolds(merl);
  const prior::PriorModel merlOnly = train(merl);
  auto fromMerlOnly = [&](const Material&) -> const prior::PriorModel& { return merlOnly; };
  for (bool noisy : {false, true}) {
    for (Sweeps s : {Sweeps::Diagonal4, Sweeps::All8}) {
      isotropyRates("MERL (tuning set)", merl, merlFolds.lookup(), s, noisy, true);
      isotropyRates("RGL + Nielsen (isotropic)", heldOut, fromMerlOnly, s, noisy, true);
      isotropyRates("anisotropic analytic", anisotropic, fromMerlOnly, s, noisy, false);
    }
  }
  return 0;
}
