// Slice-sum reconstruction: the resolved mapping, docs/method.md §3.5's worked example, the isotropic
// reduction.
#include "slicecap/recon/slice_sum.hpp"

#include <gtest/gtest.h>

#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/recon/errors.hpp"
#include "slicecap/recon/slice_extraction.hpp"

namespace slicecap::recon {
namespace {

Slice regularSlice(SliceKind kind, ElevationPair pair, const std::vector<double>& values) {
  Slice s{{kind, pair}, {}};
  const double step = 360.0 / double(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) {
    const AzimuthPair at = slicePoint(kind, double(k) * step);
    s.samples.push_back({{double(pair.thetaIDeg), at.phiIDeg},
                         {double(pair.thetaVDeg), at.phiVDeg},
                         Rgb::gray(values[k])});
  }
  return s;
}

TEST(SliceCoordinates, MatchTheChecksOfMethodSection32) {
  EXPECT_DOUBLE_EQ(sliceCoordinates(330, 30).diagonalDeg, 30.0) << "a point on the diagonal line";
  EXPECT_DOUBLE_EQ(sliceCoordinates(100, 115).axialDeg, 100.0) << "a point on the axial line";
  EXPECT_DOUBLE_EQ(sliceCoordinates(345, 0).axialDeg, 165.0);
  EXPECT_DOUBLE_EQ(sliceCoordinates(345, 0).diagonalDeg, 7.5);
  EXPECT_DOUBLE_EQ(sliceCoordinates(30, 90).axialDeg, 52.5);
  EXPECT_DOUBLE_EQ(sliceCoordinates(30, 90).diagonalDeg, 210.0);
}

TEST(SliceSum, ReproducesTheWorkedExampleOfSection35) {
  std::vector<double> axial(24, 0.22), diagonal(24, 0.5);
  axial[3] = 0.20;
  axial[4] = 0.24;
  axial[10] = 0.18;
  axial[20] = 0.26;
  diagonal[0] = 0.10;
  diagonal[1] = 0.90;
  const Subspace s = reconstructSubspace(regularSlice(SliceKind::Axial, {75, 75}, axial),
                                         regularSlice(SliceKind::Diagonal, {75, 75}, diagonal));
  // (phi_i, phi_v) = (30, 90) is azimuth 2 of the light ring and 6 of the view ring.
  EXPECT_NEAR(s.at(2, 6).r(), 0.50, 1e-12);
  // The isotropic variant reads s_D(210) = s_D[14] = 0.5 at the same point.
  const Subspace iso =
      reconstructIsotropicSubspace(regularSlice(SliceKind::Diagonal, {75, 75}, diagonal));
  EXPECT_NEAR(iso.at(2, 6).r(), 0.50, 1e-12);
}

TEST(SliceSum, StaysWithinTheSlicesRange) {
  const auto ward = models::findMaterial("satin-blue-45");
  const SliceSet slices = extractSlices(models::tabulate(*ward));
  for (ElevationPair pair : kMeasuredPairs) {
    const Slice& a = *slices.find({SliceKind::Axial, pair});
    const Slice& d = *slices.find({SliceKind::Diagonal, pair});
    const PeriodicSignal sa = toSignal(a), sd = toSignal(d);
    const Subspace s = reconstructSubspace(a, d);
    for (int p = 0; p < s.lightRing().count; ++p) {
      for (int q = 0; q < s.viewRing().count; ++q) {
        for (std::size_t c = 0; c < 3; ++c) {
          EXPECT_GE(s.at(p, q)[c], std::min(sa.minimum()[c], sd.minimum()[c]) - 1e-12);
          EXPECT_LE(s.at(p, q)[c], std::max(sa.maximum()[c], sd.maximum()[c]) + 1e-12);
        }
      }
    }
  }
}

// Slices measured straight from a model (no table in between), as a perfect rig would.
SliceSet analyticSlices(const models::ReflectanceModel& model) {
  SliceSet slices;
  for (ElevationPair pair : kMeasuredPairs) {
    const int count = samplesPerSlice(pair, {});
    for (SliceKind kind : {SliceKind::Axial, SliceKind::Diagonal}) {
      for (int k = 0; k < count; ++k) {
        const AzimuthPair at = slicePoint(kind, k * 360.0 / count);
        const Direction light{double(pair.thetaIDeg), at.phiIDeg},
            view{double(pair.thetaVDeg), at.phiVDeg};
        slices.add({kind, pair},
                   {light, view, model.evaluate(toUnitVector(light), toUnitVector(view))});
      }
    }
  }
  return slices;
}

TEST(SliceSum, IsotropicMaterialsGiveTheEquation5Result) {
  // docs/method.md §3.3-3.4: on an isotropic material the axial slice is constant and eq. 2-4 reduce
  // to eq. 5 exactly (the constant lies within the diagonal slice's range).
  const auto model = models::makeBlinnPhong({0.1, 0.2, 0.3}, {0.5, 0.5, 0.5}, 20.0);
  const SliceSet slices = analyticSlices(*model);
  for (ElevationPair pair : kMeasuredPairs) {
    const Subspace full = reconstructSubspace(*slices.find({SliceKind::Axial, pair}),
                                              *slices.find({SliceKind::Diagonal, pair}));
    const Subspace iso = reconstructIsotropicSubspace(*slices.find({SliceKind::Diagonal, pair}));
    for (int p = 0; p < full.lightRing().count; ++p) {
      for (int q = 0; q < full.viewRing().count; ++q) {
        for (std::size_t c = 0; c < 3; ++c)
          EXPECT_NEAR(full.at(p, q)[c], iso.at(p, q)[c], 1e-12);
      }
    }
  }
}

TEST(SliceSum, ReproducesIsotropicTablesWhereTheSlicePositionsFall) {
  // At 75/75 a grid point maps to w* = 180 + (phi_v - phi_i) / 2: on a diagonal sample when the
  // azimuth difference is a multiple of 30 deg, halfway between two otherwise. Where it falls on a
  // sample, an isotropic table must come back exactly, from the full method as from eq. 5.
  const auto model = models::makeBlinnPhong({0.1, 0.2, 0.3}, {0.5, 0.5, 0.5}, 20.0);
  const Abrdf table = models::tabulate(*model);
  const SliceSet slices = extractSlices(table);
  const Subspace iso = reconstructIsotropicSubspace(*slices.find({SliceKind::Diagonal, {75, 75}}));
  const Subspace full = reconstructSubspace(*slices.find({SliceKind::Axial, {75, 75}}),
                                            *slices.find({SliceKind::Diagonal, {75, 75}}));
  const Subspace truth = Subspace::fromTable(table, {75, 75});
  int checked = 0;
  for (int p = 0; p < 24; ++p) {
    for (int q = 0; q < 24; ++q) {
      if ((q - p) % 2 != 0) continue;
      ++checked;
      EXPECT_NEAR(iso.at(p, q).g(), truth.at(p, q).g(), 1e-6) << p << "," << q;
      EXPECT_NEAR(full.at(p, q).g(), truth.at(p, q).g(), 1e-6) << p << "," << q;
    }
  }
  EXPECT_EQ(checked, 24 * 12);
}

TEST(SliceSum, TorusRulesAgreeOnTwofoldSymmetricMaterials) {
  const auto ward = models::makeWard({0.1, 0.1, 0.1}, {0.3, 0.3, 0.3}, 0.1, 0.4, 30.0);
  const SliceSet slices = extractSlices(models::tabulate(*ward));
  const Slice& a = *slices.find({SliceKind::Axial, {75, 75}});
  const Slice& d = *slices.find({SliceKind::Diagonal, {75, 75}});
  const Subspace square = reconstructSubspace(a, d, TorusRule::FundamentalSquare);
  const Subspace symmetric = reconstructSubspace(a, d, TorusRule::PiSymmetric);
  for (int p = 0; p < 24; ++p) {
    for (int q = 0; q < 24; ++q)
      EXPECT_NEAR(square.at(p, q).r(), symmetric.at(p, q).r(), 1e-6);
  }
}

TEST(SliceSum, RejectsMismatchedOrEmptySlices) {
  const Slice a = regularSlice(SliceKind::Axial, {30, 30}, std::vector<double>(12, 1.0));
  const Slice d = regularSlice(SliceKind::Diagonal, {75, 75}, std::vector<double>(24, 1.0));
  EXPECT_THROW(reconstructSubspace(a, d), ReconstructionError);
  EXPECT_THROW(reconstructSubspace(d, a), ReconstructionError);
  const Slice empty{{SliceKind::Diagonal, {30, 30}}, {}};
  try {
    reconstructIsotropicSubspace(empty);
    FAIL() << "expected ReconstructionError";
  } catch (const ReconstructionError& e) {
    EXPECT_NE(std::string(e.what()).find("diagonal 30/30"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slicecap::recon
