// A camera's tone curve: how its encoded output relates to linear light, as a monotone table.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace slicecap {

/// \brief A strictly increasing map from linear light to the encoded output, both in [0, 1]
/// (1 = full scale), piecewise linear between its points, so that decode() inverts encode()
/// exactly. ISPs apply such a table (Raspberry Pi's tuning files call it `rpi.contrast`
/// `gamma_curve`); a curve measured at sweep start has the same form.
class ToneCurve {
 public:
  /// \brief Points (linear, encoded) from (0, 0) to (1, 1), both coordinates strictly increasing.
  /// Throws CoreError naming the curve and the point that breaks this.
  ToneCurve(std::string name, std::vector<std::pair<double, double>> points);

  /// \brief The sRGB transfer curve (IEC 61966-2-1), tabulated finely enough that its error is
  /// below 1e-4 of full scale.
  static ToneCurve srgb();
  /// \brief The identity (a camera delivering linear samples).
  static ToneCurve linear();
  /// \brief The `rpi.contrast` `gamma_curve` of Raspberry Pi's tuning file for the IMX708
  /// (camera module 3, `src/ipa/rpi/vc4/data/imx708.json` in raspberrypi/libcamera), a 16-bit
  /// table scaled to [0, 1]: what the Pi's ISP puts on processed frames of that sensor.
  static ToneCurve imx708Tuning();

  /// \brief The encoded value of `linear` (clamped to [0, 1]).
  double encode(double linear) const;
  /// \brief The linear value of `encoded` (clamped to [0, 1]).
  double decode(double encoded) const;

  const std::string& name() const { return name_; }
  const std::vector<std::pair<double, double>>& points() const { return points_; }

 private:
  std::string name_;
  std::vector<std::pair<double, double>> points_;
};

}  // namespace slicecap
