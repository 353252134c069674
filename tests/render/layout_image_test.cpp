// The layout image shows exactly the metrics' encoding; the difference of equal tables is black
// and scales by the gain.
#include "slicecap/render/layout_image.hpp"

#include <gtest/gtest.h>

#include "../support/material_table.hpp"
#include "slicecap/eval/metrics.hpp"
#include "slicecap/render/canvas.hpp"
#include "slicecap/render/render_error.hpp"

namespace slicecap::render {
namespace {

using test::tableOf;

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
  EXPECT_THROW(layoutImage(table, 0.0), render::RenderError);
  EXPECT_THROW(layoutImage(table, peak, 0), render::RenderError);
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

}  // namespace
}  // namespace slicecap::render
