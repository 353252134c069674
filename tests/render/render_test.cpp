// Pictures: the layout shows exactly the metrics' encoding, differences of equal tables are
// black, text and spheres draw where they should.
#include <gtest/gtest.h>

#include <numbers>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/models/reflectance_model.hpp"
#include "slicecap/render/canvas.hpp"
#include "slicecap/render/layout_image.hpp"
#include "slicecap/render/sheets.hpp"
#include "slicecap/render/sphere_render.hpp"

namespace slicecap::render {
namespace {

Abrdf tableOf(const char* material) {
  return models::tabulate(*models::findMaterial(material));
}

TEST(Render, LayoutShowsThePapersEncodingInLightRowsAndViewColumns) {
  const Abrdf table = tableOf("satin-blue-45");
  const double peak = eval::cosWeightedMaximum(table);
  const int pixels = 2;
  const Canvas layout = layoutImage(table, peak, pixels);
  ASSERT_EQ(layout.width(), 81 * pixels + 5);
  ASSERT_EQ(layout.height(), layout.width());
  const auto encoded = eval::encodePaper8Bit(table, peak);
  // Light 40 (ring 4: four ring lines above it), view 70 (ring 5: five lines left of it).
  const int light = 40, view = 70;
  const Colour got = layout.at(view * pixels + 5, light * pixels + 4);
  const std::size_t o = (std::size_t(light) * 81 + view) * 3;
  EXPECT_EQ(got, (Colour{encoded[o], encoded[o + 1], encoded[o + 2]}));
  EXPECT_THROW(layoutImage(table, 0.0), std::invalid_argument);
  EXPECT_THROW(layoutImage(table, peak, 0), std::invalid_argument);
}

TEST(Render, DifferenceOfEqualTablesIsBlackAndScalesByTheGain) {
  const Abrdf table = tableOf("blue-plastic");
  const double peak = eval::cosWeightedMaximum(table);
  const Canvas same = differenceImage(table, table, peak, 10, 1);
  for (int l = 0; l < 81; l += 9) {
    for (int v = 0; v < 81; v += 7)
      EXPECT_EQ(same.at(v + bonn::ringOfIndex(v), l + bonn::ringOfIndex(l)), kBlack);
  }
  Abrdf darker = table;
  darker.channel(0, 0, 2) *= 0.9f;
  const auto a = eval::encodePaper8Bit(table, peak), b = eval::encodePaper8Bit(darker, peak);
  const int step = std::abs(int(a[2]) - int(b[2]));
  ASSERT_GT(step, 0);
  EXPECT_EQ(differenceImage(table, darker, peak, 10, 1).at(0, 0)[2], std::min(255, 10 * step));
}

TEST(Render, TextDrawsInsideItsBoxOnly) {
  Canvas canvas(100, 20);
  const int end = canvas.drawText(2, 3, "dE 1.25", kWhite);
  EXPECT_EQ(end, 2 + 6 * 7) << "the next character's position";
  int lit = 0;
  for (int y = 0; y < canvas.height(); ++y) {
    for (int x = 0; x < canvas.width(); ++x) {
      if (canvas.at(x, y) != kWhite) continue;
      ++lit;
      EXPECT_TRUE(x >= 2 && x < 2 + textWidth("dE 1.25") && y >= 3 && y < 3 + textHeight())
          << x << "," << y;
    }
  }
  EXPECT_GT(lit, 20);
  canvas.drawText(95, 18, "clipped");  // partly outside: clipped, no error
  EXPECT_EQ(canvas.toPng().width, 100);
}

TEST(Render, ALambertianSphereLitFromTheViewerIsBrightestInTheMiddle) {
  const Canvas sphere =
      renderSphere(tableOf("matte-paint"), {0.0, 0.0}, 41, 0.6 / std::numbers::pi);
  const Colour centre = sphere.at(20, 20), rim = sphere.at(20, 2);
  EXPECT_GT(centre[0], rim[0]);
  EXPECT_EQ(sphere.at(0, 0), kSheetBackground) << "outside the disc";
  // Symmetric under a quarter turn for an isotropic material lit along the axis.
  EXPECT_EQ(sphere.at(30, 20), sphere.at(20, 30));
  EXPECT_THROW(renderSphere(tableOf("matte-paint"), {0.0, 0.0}, 4, 1.0), std::invalid_argument);
}

TEST(Render, SheetsHaveAPanelPerReconstructionAndRejectABlackReference) {
  const Abrdf truth = tableOf("satin-red-90");
  const std::vector<SheetPanel> one{{"b", &truth, {"dE 0"}}};
  const std::vector<SheetPanel> two{{"b", &truth, {"dE 0"}}, {"a", &truth, {"dE 0"}}};
  const Canvas narrow = evaluationSheet("satin", truth, {"reference"}, one);
  const Canvas wide = evaluationSheet("satin", truth, {"reference"}, two);
  EXPECT_GT(wide.width(), narrow.width());
  EXPECT_THROW(evaluationSheet("black", Abrdf{}, {}, one), std::invalid_argument);
  EXPECT_THROW(evaluationSheet("satin", truth, {}, {{"x", nullptr, {}}}), std::invalid_argument);
  EXPECT_GT(previewSheet("satin", {"line"}, truth).width(), layoutSide(3));
  EXPECT_THROW(previewSheet("black", {}, Abrdf{}), std::invalid_argument);
}

}  // namespace
}  // namespace slicecap::render
