// The canvas draws text inside its box only and clips what falls outside.
#include "slicecap/render/canvas.hpp"

#include <gtest/gtest.h>

namespace slicecap::render {
namespace {

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

}  // namespace
}  // namespace slicecap::render
