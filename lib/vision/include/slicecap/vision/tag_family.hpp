// The official AprilTag tag36h11 bitmaps, taken from the AprilTag library itself.
#pragma once

#include <array>
#include <cstdint>

namespace slicecap::vision {

/// \brief Number of codes in tag36h11.
inline constexpr int kTag36h11Count = 587;
/// \brief Cells across a tag36h11 image: a white ring, a black ring, 6 x 6 data cells.
inline constexpr int kTagTotalCells = 10;
/// \brief Cells across the black border square (the "tag size").
inline constexpr int kTagBorderCells = 8;

/// \brief A tag image as the AprilTag library renders it (apriltag_to_image): 10 x 10 cells,
/// row 0 at the top, true = white. An upright print of it is detected with corners bottom-left,
/// bottom-right, top-right, top-left.
using TagBitmap = std::array<std::array<bool, kTagTotalCells>, kTagTotalCells>;

/// \brief The bitmap of tag36h11 code `id`; throws std::out_of_range outside 0..586.
TagBitmap tag36h11Bitmap(int id);

}  // namespace slicecap::vision
