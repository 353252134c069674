// The built-in target layout and the checks a target read from a file must pass.
#include "slicecap/vision/target.hpp"

#include <cmath>
#include <set>
#include <stdexcept>

#include "slicecap/vision/tag_family.hpp"
#include "slicecap/vision/vision_error.hpp"

namespace slicecap::vision {
namespace {

bool fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

std::string number(double v) {
  std::string text = std::to_string(v);
  text.erase(text.find_last_not_of('0') + 1);
  if (!text.empty() && text.back() == '.') text.pop_back();
  return text;
}

// Tags per side of the square ring whose tag squares run from -ringMm to +ringMm.
int tagsPerSide(const TargetParams& p, double ringMm) {
  return static_cast<int>(std::floor((2 * ringMm + p.markerGapMm) / (p.markerMm + p.markerGapMm)));
}

double ringHalfWidthMm(const TargetParams& p) {
  return p.windowMm / 2 + p.bandMm + p.markerGapMm + p.markerMm;
}

Marker uprightMarker(int id, double sizeMm, PointMm centre) {
  const double h = sizeMm / 2;
  return {id,
          sizeMm,
          {{{centre.xMm - h, centre.yMm - h},
            {centre.xMm + h, centre.yMm - h},
            {centre.xMm + h, centre.yMm + h},
            {centre.xMm - h, centre.yMm + h}}}};
}

bool albedoInRange(const Rgb& albedo) {
  for (double c : albedo.channel) {
    if (!(c > 0.0 && c <= 1.0)) return false;
  }
  return true;
}

bool insideRect(const RectMm& outer, const RectMm& inner) {
  return inner.xMinMm >= outer.xMinMm && inner.yMinMm >= outer.yMinMm &&
         inner.xMaxMm <= outer.xMaxMm && inner.yMaxMm <= outer.yMaxMm;
}

}  // namespace

PointMm Marker::centre() const {
  PointMm c;
  for (const PointMm& p : cornersMm) {
    c.xMm += p.xMm / 4;
    c.yMm += p.yMm / 4;
  }
  return c;
}

const Marker* TargetGeometry::findMarker(int id) const {
  for (const Marker& m : markers) {
    if (m.id == id) return &m;
  }
  return nullptr;
}

std::string toString(PatchKind kind) {
  return kind == PatchKind::White ? "white" : "black";
}

bool TargetParams::isValid(std::string* error) const {
  const std::pair<const char*, double> lengths[] = {{"window", windowMm},
                                                    {"band", bandMm},
                                                    {"marker", markerMm},
                                                    {"marker-gap", markerGapMm},
                                                    {"margin", marginMm}};
  for (const auto& [name, value] : lengths) {
    if (!std::isfinite(value) || value <= 0.0)
      return fail(error, std::string("--") + name + " must be a positive length in mm");
  }
  if (windowMm < 10.0 || windowMm > 200.0)
    return fail(error, "--window must be 10 to 200 mm, not " + number(windowMm));
  if (markerMm < kTagBorderCells)
    return fail(error, "--marker must be at least 8 mm (1 mm cells), not " + number(markerMm));
  if (bandMm < 6.0) return fail(error, "--band must be at least 6 mm (the black patch sits in it)");
  if (markerGapMm < markerMm / kTagBorderCells)
    return fail(error, "--marker-gap must be at least one tag cell (marker / 8 mm)");
  if (marginMm < markerMm / kTagBorderCells)
    return fail(error, "--margin must be at least one tag cell (marker / 8 mm)");
  for (const auto& [name, value] :
       {std::pair{"paper-albedo", paperAlbedo}, std::pair{"ink-albedo", inkAlbedo}}) {
    if (!(value > 0.0 && value <= 1.0))
      return fail(error, std::string("--") + name + " must be in (0, 1]");
  }
  if (inkAlbedo >= paperAlbedo) return fail(error, "--ink-albedo must be below --paper-albedo");
  const int count = 4 * (tagsPerSide(*this, ringHalfWidthMm(*this)) - 1);
  if (firstId < 0 || firstId + count > kTag36h11Count)
    return fail(error, "--first-id: ids " + std::to_string(firstId) + ".." +
                           std::to_string(firstId + count - 1) + " do not all exist in tag36h11");
  return true;
}

TargetGeometry buildTarget(const TargetParams& p) {
  std::string error;
  if (!p.isValid(&error)) throw VisionError(error);
  TargetGeometry target;
  const double w = p.windowMm / 2;
  const double band = w + p.bandMm;
  const double ring = ringHalfWidthMm(p);
  const double outer = ring + p.marginMm;
  target.name = "slicecap-w" + number(p.windowMm) + "-m" + number(p.markerMm);
  target.sheet = {-outer, -outer, outer, outer};
  target.window = {-w, -w, w, w};
  target.paperAlbedo = Rgb::gray(p.paperAlbedo);
  target.inkAlbedo = Rgb::gray(p.inkAlbedo);

  // The ring: n tags a side, corner tags shared, placed counter-clockwise from the bottom-left.
  const int n = tagsPerSide(p, ring);
  const double first = -ring + p.markerMm / 2;
  const double step = (2 * ring - p.markerMm) / (n - 1);
  std::vector<PointMm> centres;
  for (int i = 0; i < n - 1; ++i)
    centres.push_back({first + i * step, first});
  for (int i = 0; i < n - 1; ++i)
    centres.push_back({-first, first + i * step});
  for (int i = 0; i < n - 1; ++i)
    centres.push_back({-first - i * step, -first});
  for (int i = 0; i < n - 1; ++i)
    centres.push_back({first, -first - i * step});
  for (std::size_t i = 0; i < centres.size(); ++i)
    target.markers.push_back(uprightMarker(p.firstId + static_cast<int>(i), p.markerMm, centres[i]));

  // The white band: four side strips and three corner squares; the bottom-left corner square
  // holds the black patch with a white surround (so it never touches a tag's quiet zone).
  const Rgb paper = target.paperAlbedo;
  target.patches = {
      {"white-left", PatchKind::White, {-band, -w, -w, w}, paper},
      {"white-right", PatchKind::White, {w, -w, band, w}, paper},
      {"white-top", PatchKind::White, {-w, w, w, band}, paper},
      {"white-bottom", PatchKind::White, {-w, -band, w, -w}, paper},
      {"white-top-left", PatchKind::White, {-band, w, -w, band}, paper},
      {"white-top-right", PatchKind::White, {w, w, band, band}, paper},
      {"white-bottom-right", PatchKind::White, {w, -band, band, -w}, paper},
  };
  const double inset = std::min(2.0, p.bandMm / 6);
  target.patches.push_back(
      {"black", PatchKind::Black, {-band + inset, -band + inset, -w - inset, -w - inset},
       target.inkAlbedo});
  return target;
}

TargetGeometry defaultTarget() {
  return buildTarget(TargetParams{});
}

std::optional<std::string> findTargetProblem(const TargetGeometry& t) {
  if (t.family != "tag36h11")
    return "family: only tag36h11 is supported, not '" + t.family + "'";
  const auto nonEmpty = [](const RectMm& r) {
    return std::isfinite(r.xMinMm) && std::isfinite(r.yMinMm) && std::isfinite(r.xMaxMm) &&
           std::isfinite(r.yMaxMm) && r.xMaxMm > r.xMinMm && r.yMaxMm > r.yMinMm;
  };
  if (!nonEmpty(t.sheet)) return std::string("sheet: not a rectangle with max > min");
  if (!nonEmpty(t.window)) return std::string("window: not a rectangle with max > min");
  if (!insideRect(t.sheet, t.window)) return std::string("window: not inside the sheet");
  if (!albedoInRange(t.paperAlbedo)) return std::string("paper_albedo: must be in (0, 1]");
  if (!albedoInRange(t.inkAlbedo)) return std::string("ink_albedo: must be in (0, 1]");
  if (t.markers.empty()) return std::string("markers: a target needs markers");
  std::set<int> ids;
  for (std::size_t i = 0; i < t.markers.size(); ++i) {
    const Marker& m = t.markers[i];
    const std::string where = "markers[" + std::to_string(i) + "] (id " + std::to_string(m.id) + ")";
    if (m.id < 0 || m.id >= kTag36h11Count) return where + ": id outside tag36h11's 0..586";
    if (!ids.insert(m.id).second) return where + ": id used twice";
    if (!(m.sizeMm > 0.0)) return where + ": size_mm must be positive";
    for (int c = 0; c < 4; ++c) {
      const PointMm& a = m.cornersMm[c];
      const PointMm& b = m.cornersMm[(c + 1) % 4];
      const PointMm& d = m.cornersMm[(c + 2) % 4];
      const double edge = std::hypot(b.xMm - a.xMm, b.yMm - a.yMm);
      const double turn = (b.xMm - a.xMm) * (d.yMm - b.yMm) - (b.yMm - a.yMm) * (d.xMm - b.xMm);
      if (!(std::abs(edge - m.sizeMm) <= 1e-3 * m.sizeMm) || !(turn > 0.0))
        return where + ": corners_mm are not a counter-clockwise square of size_mm";
      if (!t.sheet.contains(a.xMm, a.yMm) && !(a.xMm == t.sheet.xMaxMm || a.yMm == t.sheet.yMaxMm))
        return where + ": a corner lies outside the sheet";
    }
  }
  for (std::size_t i = 0; i < t.patches.size(); ++i) {
    const Patch& p = t.patches[i];
    const std::string where = "patches[" + std::to_string(i) + "] (" + p.name + ")";
    if (p.name.empty()) return "patches[" + std::to_string(i) + "]: name is empty";
    if (!nonEmpty(p.rect)) return where + ": rect is not a rectangle with max > min";
    if (!insideRect(t.sheet, p.rect)) return where + ": rect is not inside the sheet";
    if (!albedoInRange(p.albedo)) return where + ": albedo must be in (0, 1]";
  }
  return std::nullopt;
}

}  // namespace slicecap::vision
