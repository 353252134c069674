// Reads an area of the target in a frame: the mean of every pixel inside it and that mean's noise.
#pragma once

#include "slicecap/capture/linear_view.hpp"

#include <string>

#include "slicecap/core/rgb.hpp"
#include "slicecap/hal/frame.hpp"
#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/pose.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::capture {

/// \brief The sensor's noise, as the white-reference test expects it (docs/capture-gates.md). A
/// pixel at linear level v (1 = full scale) varies with variance readNoise^2 + v * gain /
/// fullWellElectrons (read noise and photon shot noise; analog gain divides the electrons a
/// full-scale value stands for), then is quantised by its encoding (8-bit sRGB: steps that grow
/// with v; 16-bit linear: 1/65535). The defaults are a small 8-bit camera module's (the virtual
/// rig's realistic sensor has the same); measure a camera's from two LED-off frames of a flat
/// field (the variance of their difference against the level).
struct SensorNoise {
  double readNoise = 0.002;           ///< standard deviation, fraction of full scale
  double fullWellElectrons = 8000.0;  ///< electrons at full scale at gain 1; 0: no shot noise
  /// \brief False, with a reason naming the field, for a negative or non-finite value.
  bool isValid(std::string* error = nullptr) const;
  /// \brief Variance of one pixel's sensor noise (before quantisation) at level `v`, full scale^2.
  double pixelVariance(double v, double gain) const;
};

/// \brief The mean of an area's pixels, per unit of exposure x gain (as read; camera units per us
/// when the frame's exposure is known), and the variance of that mean the noise model expects.
struct AreaReading {
  Rgb mean;
  Rgb variance;  ///< of `mean`, in its units squared
  int pixels = 0;
  bool inside = false;   ///< the whole area lies in the image and holds at least one pixel
  bool clipped = false;  ///< a pixel channel of it at or above the clip fraction of full scale
  /// \brief 8-bit frames: per channel, the fraction of the pixels at code 0 (black or below it,
  /// as the camera's processing clips them); 0 for linear 16-bit frames, which keep what is below
  /// black.
  Rgb atBlack;
};

/// \brief Where and how to read an area.
struct AreaSpec {
  vision::RectMm rectMm;  ///< on the target plane
  /// \brief Pixels closer than this to the area's projected outline are left out (edge blur, the
  /// pose's error, the neighbour's colour bleeding in).
  double insetPx = 0.0;
  double clipFraction = 0.98;  ///< 2 or more: nothing counts as clipped
};

/// \brief Averages every pixel whose centre lies inside `area` projected into `frame` through
/// `pose` (its outline sampled along each edge, so lens distortion bends it), at least
/// `insetPx` from the outline. The variance sums each pixel's sensor variance and quantisation
/// (step^2 / 12) over the pixel count squared, plus the quantisation bias that noise too small to
/// dither leaves in a mean (at most step / pi * exp(-2 pi^2 sigma^2 / step^2) for Gaussian noise
/// sigma), so a noise-free 8-bit frame is not taken for exact. 8-bit codes are decoded through
/// `codes` (sRGB, or the curve measured at sweep start). Where an 8-bit area's pixels near black
/// came clipped at code 0 (an ISP's output cannot go below black) and their spread is one
/// Gaussian's, the mean is that Gaussian's (censored_mean.hpp), not the clipped pixels'.
AreaReading readArea(const hal::Frame& frame, const vision::Pose& pose,
                     const vision::CameraModel& camera, const AreaSpec& area,
                     const SensorNoise& noise, const CodeTable& codes = CodeTable::srgb());

/// \brief The quantisation step of `encoding` at linear level `v` (full scale 1): for 8-bit sRGB
/// the linear width of the code that holds v.
double quantisationStep(PixelEncoding encoding, double v);

}  // namespace slicecap::capture
