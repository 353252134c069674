// The sphere render: a Lambertian sphere lit from the viewer is brightest in the middle.
#include "slicecap/render/sphere_render.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "../support/material_table.hpp"
#include "slicecap/render/canvas.hpp"
#include "slicecap/render/render_error.hpp"

namespace slicecap::render {
namespace {

using test::tableOf;

TEST(Render, ALambertianSphereLitFromTheViewerIsBrightestInTheMiddle) {
  const Canvas sphere =
      renderSphere(tableOf("matte-paint"), {0.0, 0.0}, 41, 0.6 / std::numbers::pi);
  const Colour centre = sphere.at(20, 20), rim = sphere.at(20, 2);
  EXPECT_GT(centre[0], rim[0]);
  EXPECT_EQ(sphere.at(0, 0), kSheetBackground) << "outside the disc";
  // Symmetric under a quarter turn for an isotropic material lit along the axis.
  EXPECT_EQ(sphere.at(30, 20), sphere.at(20, 30));
  EXPECT_THROW(renderSphere(tableOf("matte-paint"), {0.0, 0.0}, 4, 1.0), render::RenderError);
}

}  // namespace
}  // namespace slicecap::render
