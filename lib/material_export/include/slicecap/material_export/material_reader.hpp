// Reading back the material JSON `slicecap fit -o` writes (docs/material-fit.md), for exporting a fit
// made earlier.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "slicecap/core/error.hpp"
#include "slicecap/fit/fitted_material.hpp"

namespace slicecap::material_export {

/// \brief A material file that is not a complete, successful fit. The message starts with the path.
class MaterialFileError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief The fitted material in `path`, in the canonical convention (FittedMaterial::canonical).
/// Throws MaterialFileError naming the file when it cannot be read, is not JSON, is not a
/// "slicecap-material" of a version this build knows, lacks a parameter or the fit's metrics (a
/// fit that was not completed), or holds a value outside its range (a negative albedo, an f0
/// outside [0, 1], an alpha <= 0, a non-finite number): exports refuse a material that was not
/// fitted rather than write a default.
fit::FittedMaterial readFittedMaterial(const std::filesystem::path& path);

}  // namespace slicecap::material_export
