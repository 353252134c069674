// The Ceres lobe fit: it converges, agrees with the closed form, and recovers known lobes.
#include "slicecap/recon/lafortune_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "slicecap/recon/argument_error.hpp"

namespace slicecap::recon {
namespace {

TEST(LobeFit, TwoElevationGroupsGiveTheClosedFormThroughTheirMeans) {
  // Noisy samples at 30 and 75 deg: least squares passes through the two group means.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<ElevationSample> samples;
  double sum30 = 0, sum75 = 0;
  for (int k = 0; k < 24; ++k) {
    samples.push_back({30.0, 0.5 + noise(rng)});
    sum30 += samples.back().value;
    samples.push_back({75.0, 0.2 + noise(rng)});
    sum75 += samples.back().value;
  }
  const LobeFitResult fit = fitElevationLobe(samples);
  ASSERT_TRUE(fit.converged) << fit.message;
  const ElevationLobe exact = closedFormLobe(30.0, sum30 / 24, 75.0, sum75 / 24);
  EXPECT_NEAR(fit.lobe.n, exact.n, 1e-6);
  EXPECT_NEAR(fit.lobe(30.0), sum30 / 24, 1e-7);
  EXPECT_NEAR(fit.lobe(75.0), sum75 / 24, 1e-7);
  EXPECT_GT(fit.iterations, 1) << "a real iterative solve from the constant start";
}

TEST(LobeFit, MeetsBothMeansWhenTheyDifferByOrdersOfMagnitude) {
  // Chrome's line at theta_i 75: a mean of 4e-4 at 30 deg against 75 at 75 deg.
  std::vector<ElevationSample> samples;
  for (int k = 0; k < 24; ++k) {
    samples.push_back({30.0, 4.065e-4 * (1.0 + 0.5 * std::sin(k))});
    samples.push_back({75.0, 74.58 * (1.0 + 0.9 * std::cos(k))});
  }
  double sum30 = 0, sum75 = 0;
  for (const auto& s : samples)
    (s.thetaDeg == 30.0 ? sum30 : sum75) += s.value;
  const LobeFitResult fit = fitElevationLobe(samples);
  ASSERT_TRUE(fit.converged) << fit.message;
  EXPECT_NEAR(fit.lobe.n, closedFormLobe(30.0, sum30 / 24, 75.0, sum75 / 24).n, 1e-8);
  EXPECT_NEAR(fit.lobe(30.0) / (sum30 / 24), 1.0, 1e-9);
}

TEST(LobeFit, ReproducesTheWorkedExampleOfSection42) {
  const std::vector<ElevationSample> means{{30.0, 0.50}, {75.0, 0.20}};
  const LobeFitResult fit = fitElevationLobe(means);
  ASSERT_TRUE(fit.converged);
  EXPECT_NEAR(fit.lobe.n, 0.7587, 1e-4);
  const auto t = [&](double theta) {
    return (fit.lobe.shape(theta) - fit.lobe.shape(30)) / (fit.lobe.shape(75) - fit.lobe.shape(30));
  };
  EXPECT_NEAR(t(45), 0.2376, 1e-4);
  EXPECT_NEAR(t(60), 0.5680, 1e-4);
  EXPECT_NEAR(fit.lobe.shape(15) / fit.lobe.shape(30), 1.0864, 1e-4);
  EXPECT_NEAR(fit.lobe.shape(0) / fit.lobe.shape(30), 1.1153, 1e-4);
}

TEST(LobeFit, RecoversAKnownLobeFromManyElevations) {
  std::vector<ElevationSample> samples;
  for (double theta = 0; theta < 80; theta += 5)
    samples.push_back({theta, 3e-3 * std::pow(std::cos(theta * std::numbers::pi / 180), 2.5)});
  const LobeFitResult fit = fitElevationLobe(samples);
  ASSERT_TRUE(fit.converged);
  EXPECT_NEAR(fit.lobe.n, 2.5, 1e-6) << "the fit is scale-free: a dark material fits as well";
  EXPECT_NEAR(fit.lobe.k, 3e-3, 1e-9);
}

TEST(LobeFit, FitsRisingCurvesWithNegativeExponents) {
  // Grazing-bright materials (velvet, retro-reflection) get brighter toward 75 deg.
  const std::vector<ElevationSample> samples{{30.0, 0.1}, {75.0, 0.4}};
  const LobeFitResult fit = fitElevationLobe(samples);
  ASSERT_TRUE(fit.converged);
  EXPECT_LT(fit.lobe.n, 0.0);
  EXPECT_NEAR(fit.lobe(75.0), 0.4, 1e-7);
}

TEST(LobeFit, RejectsUnusableInput) {
  EXPECT_THROW(fitElevationLobe(std::vector<ElevationSample>{}), recon::ReconArgumentError);
  EXPECT_THROW(fitElevationLobe(std::vector<ElevationSample>{{30, 1}, {30, 2}}),
               recon::ReconArgumentError);
  EXPECT_THROW(fitElevationLobe(std::vector<ElevationSample>{{30, 1}, {90, 2}}),
               recon::ReconArgumentError);
  EXPECT_THROW(fitElevationLobe(std::vector<ElevationSample>{{30, NAN}, {75, 2}}),
               recon::ReconArgumentError);
  // A non-finite value is named as such, not as an angle out of range.
  try {
    fitElevationLobe(std::vector<ElevationSample>{{30, 1}, {75, INFINITY}});
    ADD_FAILURE() << "an infinite sample was fitted";
  } catch (const recon::ReconArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("sample value is not finite (inf)"), std::string::npos)
        << e.what();
  }
  LobeFitParams bad;
  bad.maxIterations = 0;
  std::string why;
  EXPECT_FALSE(bad.isValid(&why));
  EXPECT_THROW(fitElevationLobe(std::vector<ElevationSample>{{30, 1}, {75, 2}}, bad),
               recon::ReconArgumentError);
}

TEST(LobeFit, ClampsDarkMeansBeforeTakingLogarithms) {
  const ElevationLobe lobe = closedFormLobe(30, 0.0, 75, 0.2);
  EXPECT_TRUE(std::isfinite(lobe.n));
  const LobeFitResult fit = fitElevationLobe(std::vector<ElevationSample>{{30, -0.01}, {75, 0.2}});
  EXPECT_TRUE(std::isfinite(fit.lobe.n));
}

}  // namespace
}  // namespace slicecap::recon

#include <ceres/gradient_checker.h>

#include "slicecap/recon/lobe_cost.hpp"

namespace slicecap::recon {
namespace {

TEST(LobeCost, AnalyticJacobiansMatchNumericDifferentiation) {
  const std::vector<ElevationSample> samples{{30, 0.5}, {30, 0.45}, {75, 0.2}, {60, 0.3}, {0, 0.7}};
  const LobeCost cost(samples, 1e-6);
  const std::vector<const ceres::Manifold*>* noManifolds = nullptr;
  const ceres::GradientChecker checker(&cost, noManifolds, ceres::NumericDiffOptions());
  for (const auto& [logK, n] : {std::pair{0.0, 1.0}, std::pair{-1.3, 0.2}, std::pair{0.7, -2.0}}) {
    const double block[2] = {logK, n};
    const double* parameters[1] = {block};
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters, 1e-7, &results)) << results.error_log;
  }
}

}  // namespace
}  // namespace slicecap::recon
