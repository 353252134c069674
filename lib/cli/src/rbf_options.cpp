// Parsing and printing of `--rbf SPEC`.
#include "slicecap/cli/rbf_options.hpp"

#include <cmath>
#include <sstream>

#include "slicecap/cli/args.hpp"

namespace slicecap::cli {
namespace {

recon::RbfKernel parseKernel(const std::string& text) {
  if (text == "mq") return recon::RbfKernel::Multiquadric;
  if (text == "imq") return recon::RbfKernel::InverseMultiquadric;
  if (text == "r") return recon::RbfKernel::Linear;
  if (text == "r3") return recon::RbfKernel::Cubic;
  throw UsageError("--rbf: kernel '" + text + "' is not one of mq, imq, r, r3");
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

double parsePositive(const std::string& key, const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value) || value <= 0.0)
    throw UsageError("--rbf: " + key + " '" + text + "' is not a positive number");
  return value;
}

}  // namespace

void applyRbfSpec(const std::string& spec, MethodOptions& options) {
  std::istringstream items(spec);
  std::string item;
  while (std::getline(items, item, ',')) {
    const std::size_t equals = item.find('=');
    if (equals == std::string::npos)
      throw UsageError("--rbf: '" + item +
                       "' is not key=value (keys: kernel, poly, r0, frame, "
                       "gamma)");
    const std::string key = item.substr(0, equals), value = item.substr(equals + 1);
    if (key == "kernel") {
      options.rbf.kernel = parseKernel(value);
    } else if (key == "poly") {
      if (value != "const" && value != "linear")
        throw UsageError("--rbf: poly '" + value + "' is not one of const, linear");
      options.rbf.polynomial =
          value == "linear" ? recon::RbfPolynomial::Linear : recon::RbfPolynomial::Constant;
    } else if (key == "r0") {
      options.rbf.shapeScale = parsePositive(key, value);
    } else if (key == "frame") {
      if (value != "relative" && value != "absolute")
        throw UsageError("--rbf: frame '" + value + "' is not one of relative, absolute");
      options.onionFrame =
          value == "absolute" ? recon::OnionFrame::Absolute : recon::OnionFrame::ViewRelative;
    } else if (key == "gamma") {
      options.rbf.valueGamma = parsePositive(key, value);
    } else {
      throw UsageError("--rbf: unknown key '" + key + "' (keys: kernel, poly, r0, frame, gamma)");
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

}  // namespace slicecap::cli
