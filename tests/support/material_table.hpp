// A named material of the catalogue as a table, as the picture tests draw them.
#pragma once

#include "slicecap/core/abrdf.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::test {

/// \brief models::findMaterial(material) tabulated; the material must be in the catalogue.
inline Abrdf tableOf(const char* material) {
  return models::tabulate(*models::findMaterial(material));
}

}  // namespace slicecap::test
