// The error lib/material_export throws for a preview mesh it cannot make.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::material_export {

/// \brief A preview mesh lib/material_export cannot make from its arguments; the message names
/// them. A material glTF cannot hold is GltfMaterialError, a fit file that cannot be read
/// MaterialFileError.
class MaterialExportError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::material_export
