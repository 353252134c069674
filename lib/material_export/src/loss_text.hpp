// A figure in a conversion loss's words: 3 significant digits, as the glTF mapping and the choice of
// its form both report them, so the two read alike.
#pragma once

#include <sstream>
#include <string>

namespace slicecap::material_export::detail {

inline std::string lossFigure(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

}  // namespace slicecap::material_export::detail
