// tag36h11 bitmaps built from the AprilTag library's own family table, exactly as its
// apriltag_to_image() draws them (that function needs libapriltag-utils, which apriltag.pc omits).
#include "slicecap/vision/tag_family.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace slicecap::vision {
namespace {

struct FamilyDeleter {
  void operator()(apriltag_family_t* family) const { tag36h11_destroy(family); }
};

const apriltag_family_t& family() {
  static const std::unique_ptr<apriltag_family_t, FamilyDeleter> instance(tag36h11_create());
  return *instance;
}

}  // namespace

TagBitmap tag36h11Bitmap(int id) {
  const apriltag_family_t& fam = family();
  if (id < 0 || id >= static_cast<int>(fam.ncodes))
    throw std::out_of_range("tag36h11 has no code " + std::to_string(id) + " (0.." +
                            std::to_string(fam.ncodes - 1) + ")");
  TagBitmap bitmap{};
  // Outer ring white, the border ring black, then every set code bit white; bit i is the
  // (nbits - 1 - i)-th bit of the code, placed at (bit_x[i], bit_y[i]) inside the border.
  for (int i = 0; i < kTagTotalCells; ++i) {
    bitmap[0][i] = bitmap[kTagTotalCells - 1][i] = true;
    bitmap[i][0] = bitmap[i][kTagTotalCells - 1] = true;
  }
  const int borderStart = (fam.total_width - fam.width_at_border) / 2;
  const std::uint64_t code = fam.codes[id];
  for (std::uint32_t i = 0; i < fam.nbits; ++i) {
    if (code & (std::uint64_t{1} << (fam.nbits - i - 1)))
      bitmap[fam.bit_y[i] + borderStart][fam.bit_x[i] + borderStart] = true;
  }
  return bitmap;
}

}  // namespace slicecap::vision
