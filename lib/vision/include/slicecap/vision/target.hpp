// The printable target: a window onto the material, white and black reference patches, and
// AprilTag tag36h11 markers around them; all geometry in the target frame, mm.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "slicecap/core/rgb.hpp"

namespace slicecap::vision {

/// \brief A point on the target plane, mm, in the target frame: origin at the window centre, x to
/// the right, y up (z out of the material; azimuth 0 along +x).
struct PointMm {
  double xMm = 0.0;
  double yMm = 0.0;
  friend constexpr bool operator==(const PointMm&, const PointMm&) = default;
};

/// \brief An axis-aligned rectangle of the target plane, mm.
struct RectMm {
  double xMinMm = 0.0, yMinMm = 0.0, xMaxMm = 0.0, yMaxMm = 0.0;
  bool contains(double xMm, double yMm) const {
    return xMm >= xMinMm && xMm < xMaxMm && yMm >= yMinMm && yMm < yMaxMm;
  }
  PointMm centre() const { return {(xMinMm + xMaxMm) / 2, (yMinMm + yMaxMm) / 2}; }
  double widthMm() const { return xMaxMm - xMinMm; }
  double heightMm() const { return yMaxMm - yMinMm; }
  friend constexpr bool operator==(const RectMm&, const RectMm&) = default;
};

/// \brief One tag36h11 marker. `sizeMm` is the edge of its black border square (the AprilTag
/// library's "tag size"); `cornersMm` are that square's corners in the order the AprilTag library
/// reports them for this tag (detection p[0..3]): for a tag printed upright, bottom-left,
/// bottom-right, top-right, top-left (counter-clockwise in the target frame). A white quiet zone
/// one cell (sizeMm / 8) wide surrounds the square.
struct Marker {
  int id = 0;
  double sizeMm = 0.0;
  std::array<PointMm, 4> cornersMm{};
  PointMm centre() const;
  friend bool operator==(const Marker&, const Marker&) = default;
};

/// \brief A white reference area (paper) or the black patch (ink).
enum class PatchKind { White, Black };

/// \brief A reference patch: a rectangle of known Lambertian albedo (linear RGB).
struct Patch {
  std::string name;  ///< e.g. "white-left", "black"
  PatchKind kind = PatchKind::White;
  RectMm rect;
  Rgb albedo;
  friend bool operator==(const Patch&, const Patch&) = default;
};

/// \brief The whole target. Everything on the sheet that is neither window, marker ink nor the
/// black patch is paper of `paperAlbedo`.
struct TargetGeometry {
  std::string name;
  std::string family = "tag36h11";
  RectMm sheet;   ///< the printed area (what the virtual rig lays on the desk)
  RectMm window;  ///< cut out: the material is seen through it
  Rgb paperAlbedo;
  Rgb inkAlbedo;
  std::vector<Marker> markers;
  std::vector<Patch> patches;
  friend bool operator==(const TargetGeometry&, const TargetGeometry&) = default;

  /// \brief The marker with this id, or nullptr.
  const Marker* findMarker(int id) const;
};

/// \brief The layout parameters of the built-in target family (lengths in mm).
struct TargetParams {
  double windowMm = 40.0;      ///< side of the square window
  double bandMm = 12.0;        ///< width of the white reference band around the window
  double markerMm = 16.0;      ///< tag size (black border square); one cell is markerMm / 8
  double markerGapMm = 4.0;    ///< least white between band and tags, and between tags
  double marginMm = 6.0;       ///< white paper outside the tag ring
  double paperAlbedo = 0.85;   ///< nominal albedo of white office paper
  double inkAlbedo = 0.04;     ///< nominal albedo of black laser toner
  int firstId = 0;             ///< markers take ids firstId, firstId + 1, ...

  /// \brief False with a reason naming the option when a length or albedo is out of range (a cell
  /// under 1 mm, a window under 10 mm, an albedo outside (0, 1], more tags than tag36h11 has).
  bool isValid(std::string* error = nullptr) const;
};

/// \brief The target of these parameters: the window centred at the origin, a white band around
/// it (four side strips and three corner squares are the white reference patches; the fourth,
/// bottom-left corner holds the black patch), a square ring of tags outside the band (ids going
/// counter-clockwise from the bottom-left corner), a paper margin. Throws VisionError
/// when !params.isValid().
TargetGeometry buildTarget(const TargetParams& params);

/// \brief buildTarget(TargetParams{}): the built-in default (40 mm window, 16 tags of 16 mm).
TargetGeometry defaultTarget();

/// \brief Checks a target read from a file: a tag36h11 family, a non-empty window inside the sheet,
/// markers with distinct valid ids whose corners form a square of their size, albedos in (0, 1],
/// patches inside the sheet. Returns the first problem (naming the marker or patch), or nullopt.
std::optional<std::string> findTargetProblem(const TargetGeometry& target);

/// \brief "white" or "black".
std::string toString(PatchKind kind);

}  // namespace slicecap::vision
