// Parsing and printing of an RBF spec (`--rbf SPEC`).
#include "slicecap/methods/rbf_spec.hpp"

#include <sstream>

#include "slicecap/methods/errors.hpp"

namespace slicecap::methods {
namespace {

recon::RbfKernel parseKernel(const std::string& text) {
  if (text == "mq") return recon::RbfKernel::Multiquadric;
  if (text == "imq") return recon::RbfKernel::InverseMultiquadric;
  if (text == "r") return recon::RbfKernel::Linear;
  if (text == "r3") return recon::RbfKernel::Cubic;
  throw MethodError("--rbf: kernel '" + text + "' is not one of mq, imq, r, r3");
}

std::string kernelName(recon::RbfKernel kernel) {
  switch (kernel) {
    case recon::RbfKernel::InverseMultiquadric:
      return "imq";
    case recon::RbfKernel::Linear:
      return "r";
    case recon::RbfKernel::Cubic:
      return "r3";
    case recon::RbfKernel::Multiquadric:
      break;
  }
  return "mq";
}

// The ranges where Method A and the uniform baseline still interpolate (measured with `slicecap
// eval`, docs/results/2026-11-23-method-a-rbf-choices.md). r0: below 0.01 the inverse
// multiquadric's diagonal tends to 1/0 (NaN, clipped to an all-zero table); above 4 the
// multiquadric is nearly flat over the centres and the system's rounding swamps the interpolant (dE
// 22 at 5, 79 at 10; from 1e10 all zeros). gamma: below 1 it expands the values the interpolant
// already overshoots (at 0.5 a third of a glossy table's entries clip to zero, at 0.1 more than
// half; further down float's range ends), and above 1000 the result loses float's precision (1e10:
// all zeros).
constexpr double kMinShapeScale = 0.01, kMaxShapeScale = 4.0;
constexpr double kMinValueGamma = 1.0, kMaxValueGamma = 1000.0;

double parseInRange(const std::string& key, const std::string& text, double lo, double hi) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(value >= lo && value <= hi)) {
    std::ostringstream range;
    range << lo << ".." << hi;
    throw MethodError("--rbf: " + key + " '" + text + "' is not a number in " + range.str());
  }
  return value;
}

}  // namespace

void applyRbfSpec(const std::string& spec, MethodOptions& options) {
  std::istringstream items(spec);
  std::string item;
  while (std::getline(items, item, ',')) {
    const std::size_t equals = item.find('=');
    if (equals == std::string::npos)
      throw MethodError("--rbf: '" + item +
                       "' is not key=value (keys: kernel, poly, r0, frame, "
                       "gamma)");
    const std::string key = item.substr(0, equals), value = item.substr(equals + 1);
    if (key == "kernel") {
      options.rbf.kernel = parseKernel(value);
    } else if (key == "poly") {
      if (value != "const" && value != "linear")
        throw MethodError("--rbf: poly '" + value + "' is not one of const, linear");
      options.rbf.polynomial =
          value == "linear" ? recon::RbfPolynomial::Linear : recon::RbfPolynomial::Constant;
    } else if (key == "r0") {
      options.rbf.shapeScale = parseInRange(key, value, kMinShapeScale, kMaxShapeScale);
    } else if (key == "frame") {
      if (value != "relative" && value != "absolute")
        throw MethodError("--rbf: frame '" + value + "' is not one of relative, absolute");
      options.onionFrame =
          value == "absolute" ? recon::OnionFrame::Absolute : recon::OnionFrame::ViewRelative;
    } else if (key == "gamma") {
      options.rbf.valueGamma = parseInRange(key, value, kMinValueGamma, kMaxValueGamma);
    } else {
      throw MethodError("--rbf: unknown key '" + key + "' (keys: kernel, poly, r0, frame, gamma)");
    }
  }
}

std::string rbfSpec(const MethodOptions& options) {
  std::ostringstream spec;
  spec << "kernel=" << kernelName(options.rbf.kernel)
       << ",poly=" << (options.rbf.polynomial == recon::RbfPolynomial::Linear ? "linear" : "const")
       << ",r0=" << options.rbf.shapeScale
       << ",frame=" << (options.onionFrame == recon::OnionFrame::Absolute ? "absolute" : "relative")
       << ",gamma=" << options.rbf.valueGamma;
  return spec.str();
}

}  // namespace slicecap::methods
