// The material in the virtual rig's window: a built-in name, a table file, or an analytic model.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "slicecap/core/abrdf.hpp"
#include "slicecap/core/error.hpp"
#include "slicecap/models/reflectance_model.hpp"

namespace slicecap::sim {

/// \brief A material specification that cannot be used; what() names it and the bad parameter.
class MaterialError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

/// \brief The BRDF of a full table at any directions (core/grid_interpolation: linear on the
/// Bonn grid; elevations above 75 deg take the 75 deg ring).
std::shared_ptr<const models::ReflectanceModel> makeTableMaterial(Abrdf table, std::string name);

/// \brief A material from its specification:
///  - a built-in name (`slicecap generate --list`), e.g. "satin-blue-45";
///  - a table file ending in .exr or .f32;
///  - "lambert:albedo=R,G,B", "ward:diffuse=R,G,B,specular=R,G,B,ax=A,ay=A,tangent=DEG",
///    "ggx:diffuse=R,G,B,f0=R,G,B,ax=A,ay=A,tangent=DEG" (a colour may be one number for gray;
///    parameters may be left out: lambert albedo 0.5; ward diffuse 0.2, specular 0.1, ax 0.1,
///    ay 0.3, tangent 0; ggx diffuse 0.05, f0 0.9, ax 0.1, ay 0.3, tangent 0);
///  - "woven", "woven:cell=MM", "woven:fine=1": a spatially varying plain weave of two satins
///    (patterned_material.hpp; cell 10 mm), which the renderer shades pixel by pixel, each
///    pixel its footprint's share of each thread; fine=1 (0 or 1): the threads mixed half and
///    half at every point.
/// Throws MaterialError naming the specification and the parameter, or io::IoError for a table.
std::shared_ptr<const models::ReflectanceModel> loadMaterial(const std::string& spec);

}  // namespace slicecap::sim
