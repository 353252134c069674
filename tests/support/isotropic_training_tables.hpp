// A small training set of isotropic analytic tables, as the prior's tests train on (a clean clone
// has no measured ones).
#pragma once

#include <vector>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::test {

/// \brief Eight Blinn-Phong tables: exponents 5, 20, 80, 300, each with diffuse 0.05 and 0.3.
inline std::vector<Abrdf> analyticTables() {
  std::vector<Abrdf> tables;
  for (double exponent : {5.0, 20.0, 80.0, 300.0}) {
    for (double diffuse : {0.05, 0.3}) {
      tables.push_back(models::tabulate(
          *models::makeBlinnPhong({diffuse, 0.5 * diffuse, 0.2}, {0.4, 0.4, 0.4}, exponent)));
    }
  }
  return tables;
}

}  // namespace slicecap::test
