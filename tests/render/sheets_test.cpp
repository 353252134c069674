// The evaluation and preview sheets: a panel per reconstruction, a black reference refused.
#include "slicecap/render/sheets.hpp"

#include <gtest/gtest.h>

#include "../support/material_table.hpp"
#include "slicecap/render/canvas.hpp"
#include "slicecap/render/layout_image.hpp"
#include "slicecap/render/render_error.hpp"

namespace slicecap::render {
namespace {

using test::tableOf;

TEST(Render, SheetsHaveAPanelPerReconstructionAndRejectABlackReference) {
  const Abrdf truth = tableOf("satin-red-90");
  const std::vector<SheetPanel> one{{"b", &truth, {"dE 0"}}};
  const std::vector<SheetPanel> two{{"b", &truth, {"dE 0"}}, {"a", &truth, {"dE 0"}}};
  const Canvas narrow = evaluationSheet("satin", truth, {"reference"}, one);
  const Canvas wide = evaluationSheet("satin", truth, {"reference"}, two);
  EXPECT_GT(wide.width(), narrow.width());
  EXPECT_THROW(evaluationSheet("black", Abrdf{}, {}, one), render::RenderError);
  EXPECT_THROW(evaluationSheet("satin", truth, {}, {{"x", nullptr, {}}}), render::RenderError);
  EXPECT_GT(previewSheet("satin", {"line"}, truth).width(), layoutSide(3));
  EXPECT_THROW(previewSheet("black", {}, Abrdf{}), render::RenderError);
}


}  // namespace
}  // namespace slicecap::render
