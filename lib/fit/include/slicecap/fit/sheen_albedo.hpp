// KHR_materials_sheen's sheen lobe and its directional albedo E, as the fit's "khr" sheen form
// evaluates them (glTF KHR_materials_sheen README: "Sheen distribution", "Sheen visibility",
// "Albedo-scaling technique").
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

namespace slicecap::fit {

/// \brief The Charlie lobe's roughness range the albedo table covers (alpha_g, the fit's
/// sheen_roughness r; glTF's sheenRoughnessFactor^2): the fit's own bounds.
inline constexpr double kSheenAlbedoMinRoughness = 0.05, kSheenAlbedoMaxRoughness = 1.0;
/// \brief Nodes of the table: cosines 0..1 (linear between them), roughness as above (cubic).
inline constexpr int kSheenAlbedoCosines = 33, kSheenAlbedoRoughnesses = 39;

/// \brief E(cos_theta, r) at the table's nodes: [roughness][cosine].
using SheenAlbedoTable =
    std::array<std::array<double, kSheenAlbedoCosines>, kSheenAlbedoRoughnesses>;

/// \brief The table, computed once on first use (thread-safe static; about 0.2 s of one core).
///
/// E(mu) = integral over the hemisphere of D_charlie(h) V_charlie(l, v) cos_l d omega_l, v at
/// polar cosine mu (floored at 1e-3: V has 1 / cos_v): a midpoint rule over theta_l (64 steps
/// over [0, pi/2]) and phi (64 steps over [0, pi], doubled: the integrand is symmetric about the
/// plane of v and the normal). The extension's sample implementation reads E from a lookup
/// texture; this table is the same integral, written from the extension's formulas.
/// python/src/slicecap/fitted_material.py computes the same table the same way.
const SheenAlbedoTable& sheenAlbedoTable();

namespace detail {

/// \brief The value of a double or of a Ceres Jet (its `a`), without naming Ceres here.
template <typename T>
double valueOf(const T& x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return x;
  } else {
    return x.a;
  }
}

/// \brief KHR_materials_sheen's "l(x, alpha_g)" of the Charlie visibility; `logX` = log(x), and
/// x = 0 gives its limit a / 1 + e (x^c -> 0 for c > 0).
template <typename T>
T charlieL(double x, double logX, const T& alpha) {
  const T w = (1.0 - alpha) * (1.0 - alpha);
  const auto mix = [&w](double a, double b) { return a + (b - a) * w; };
  const T a = mix(21.5473, 25.3245), b = mix(3.82987, 3.32435), c = mix(0.19823, 0.16801);
  const T d = mix(-1.97760, -1.27393), e = mix(-4.32054, -4.85967);
  using std::exp;
  const T power = x > 0.0 ? T(exp(c * logX)) : T(0.0);
  return a / (1.0 + b * power) + d * x + e;
}

/// \brief KHR_materials_sheen's lambda_sheen(cos_theta, alpha_g).
template <typename T>
T charlieLambda(double cosTheta, const T& alpha) {
  using std::exp;
  if (std::abs(cosTheta) < 0.5) return exp(charlieL(cosTheta, std::log(cosTheta), alpha));
  const double x = 1.0 - cosTheta;
  return exp(2.0 * charlieL(0.5, std::log(0.5), alpha) -
             charlieL(x, x > 0.0 ? std::log(x) : 0.0, alpha));
}

/// \brief KHR_materials_sheen's sheen_visibility (the "Charlie" one).
template <typename T>
T charlieVisibility(double cosL, double cosV, const T& alpha) {
  return 1.0 / ((1.0 + charlieLambda(cosV, alpha) + charlieLambda(cosL, alpha)) *
                (4.0 * cosV * cosL));
}

/// \brief E(cos_theta, r) from the table: linear in the cosine, Catmull-Rom in r (so that the
/// fit's derivative in r is continuous); r is held in the table's range.
template <typename T>
T sheenAlbedo(double cosTheta, const T& roughness) {
  const SheenAlbedoTable& table = sheenAlbedoTable();
  const double mu = std::clamp(cosTheta, 0.0, 1.0) * (kSheenAlbedoCosines - 1);
  const int i = std::min(static_cast<int>(mu), kSheenAlbedoCosines - 2);
  const double fMu = mu - i;
  constexpr double step =
      (kSheenAlbedoMaxRoughness - kSheenAlbedoMinRoughness) / (kSheenAlbedoRoughnesses - 1);
  T at = (roughness - kSheenAlbedoMinRoughness) / step;
  if (at < T(0.0)) at = T(0.0);
  if (at > T(kSheenAlbedoRoughnesses - 1.0)) at = T(kSheenAlbedoRoughnesses - 1.0);
  const int j = std::min(static_cast<int>(valueOf(at)), kSheenAlbedoRoughnesses - 2);
  const T t = at - static_cast<double>(j);
  const auto node = [&](int k) {
    const auto& row = table[static_cast<std::size_t>(std::clamp(k, 0, kSheenAlbedoRoughnesses - 1))];
    return row[static_cast<std::size_t>(i)] * (1.0 - fMu) + row[static_cast<std::size_t>(i) + 1] * fMu;
  };
  const double p0 = node(j - 1), p1 = node(j), p2 = node(j + 1), p3 = node(j + 2);
  // Catmull-Rom through p1 (t = 0) and p2 (t = 1); the end rows repeat, a one-sided tangent.
  const T t2 = t * t, t3 = t2 * t;
  return 0.5 * (2.0 * p1 + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3);
}

}  // namespace detail

/// \brief E(cos_theta, r), the directional albedo of KHR_materials_sheen's lobe (Charlie D and
/// visibility) of roughness r = alpha_g: what the extension's albedo scaling takes from the base.
inline double sheenAlbedo(double cosTheta, double roughness) {
  return detail::sheenAlbedo(cosTheta, roughness);
}

}  // namespace slicecap::fit
