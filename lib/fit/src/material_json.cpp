// Every parameter with its unit and convention, the candidates and why one was chosen, the metrics.
#include "slicecap/fit/material_json.hpp"

#include <ostream>
#include <string>

#include "slicecap/io/file_replacement.hpp"

namespace slicecap::fit {
namespace {

using json = nlohmann::ordered_json;

json orNull(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

json rgbParameter(const Rgb& value, const std::array<std::optional<double>, 3>& sigma,
                  const char* unit) {
  return {{"value", {value[0], value[1], value[2]}},
          {"sigma", {orNull(sigma[0]), orNull(sigma[1]), orNull(sigma[2])}},
          {"unit", unit}};
}

json scalarParameter(double value, const std::optional<double>& sigma, const char* unit) {
  return {{"value", value}, {"sigma", orNull(sigma)}, {"unit", unit}};
}

json metricsJson(const eval::Metrics& m) {
  return {{"delta_e", m.deltaE},
          {"rmse", m.rmse},
          {"psnr_db", m.psnrDb},
          {"relative_rmse", m.relativeRmse}};
}

json parametersJson(const FittedMaterial& m, const ParameterSigmas& s) {
  json p = {
      {"diffuse_albedo", rgbParameter(m.diffuseAlbedo, s.diffuseAlbedo,
                                      "Lambertian albedo, linear RGB; BRDF = albedo / pi (1/sr)")},
      {"specular_f0", rgbParameter(m.specularF0, s.specularF0,
                                   "Schlick reflectance at normal incidence, linear RGB, 0..1")},
      {"specular_f90", scalarParameter(m.specularF90, s.specularF90,
                                       "Schlick reflectance at grazing incidence, grey, 0..1 "
                                       "(glTF KHR_materials_specular 'specular')")},
      {"alpha_tangent", scalarParameter(m.alphaTangent, s.alphaTangent,
                                        "GGX alpha (= perceptual roughness^2) along the tangent")},
      {"alpha_bitangent",
       scalarParameter(m.alphaBitangent, s.alphaBitangent,
                       "GGX alpha (= perceptual roughness^2) across the tangent")},
      {"tangent_deg",
       scalarParameter(m.tangentDeg, s.tangentDeg,
                       "deg, counter-clockwise from the table's azimuth-0 axis, [0, 180)")},
  };
  if (hasSheen(m.model)) {
    p["sheen_colour"] = rgbParameter(m.sheenColour, s.sheenColour,
                                     "Charlie sheen tint, linear RGB (multiplies D_sheen V); glTF sheenColorFactor, 0..1, in the khr_materials_sheen form");
    p["sheen_roughness"] = scalarParameter(m.sheenRoughness, s.sheenRoughness,
                                           "Charlie roughness r (lobe sin^(1/r) theta_h), 0..1");
  }
  if (hasCoat(m.model)) {
    p["coat_weight"] = scalarParameter(m.coatWeight, s.coatWeight,
                                       "clear coat weight w, 0..1 (glTF KHR_materials_clearcoat "
                                       "clearcoatFactor)");
    p["coat_alpha"] = scalarParameter(m.coatAlpha, s.coatAlpha,
                                      "GGX alpha of the isotropic coat lobe (= clearcoatRoughness^2)");
  }
  return p;
}

// The form of every sheen in the file, the chosen material's and the candidates' (fitMaterial
// fits them all in one form, FitOptions::sheenForm).
SheenForm sheenFormOf(const FitResult& result) { return result.material.sheenForm; }

std::string brdfConvention(SheenForm form) {
  const std::string base =
      "diffuse_albedo / pi + F_schlick(specular_f0, specular_f90, l.h) D_ggx "
      "G2_smith_height_correlated / (4 cos_i cos_v)";
  const std::string sheen =
      form == SheenForm::Khr
          ? "; with a sheen (sheen_form khr_materials_sheen, glTF KHR_materials_sheen's layering): "
            "sheen_colour D_charlie V_charlie + base min(1 - s E(cos_v), 1 - s E(cos_i)), "
            "s = max(sheen_colour), V_charlie the extension's Charlie visibility and E its "
            "directional albedo, alpha_g = sheen_roughness"
          : " [+ sheen_colour D_charlie / (4 (cos_i + cos_v - cos_i cos_v))] (sheen_form additive)";
  return base + sheen +
         "; with a coat, base (1 - w Fc) + w Fc D_ggx(coat_alpha) G2 / (4 cos_i cos_v), Fc = 0.04 "
         "+ 0.96 (1 - cos_v)^5 (glTF KHR_materials_clearcoat, IOR 1.5), w = coat_weight";
}

}  // namespace

json materialJson(const FitResult& result, const std::string& source) {
  json candidates = json::array();
  for (const CandidateFit& c : result.candidates) {
    candidates.push_back({{"model", toString(c.model)},
                          {"lobe", c.isotropicLobe ? "isotropic" : "anisotropic"},
                          {"metrics", metricsJson(c.metrics)},
                          {"cost", c.cost},
                          {"iterations", c.iterations},
                          {"starts_tried", c.startsTried},
                          {"solves_converged", c.solvesConverged},
                          {"best_start_tangent_deg", c.bestStartTangentDeg},
                          {"parameters", parametersJson(c.material, c.sigmas)}});
  }
  return {
      {"format", kMaterialFormat},
      {"format_version", kMaterialFormatVersion},
      {"source", source},
      {"model", toString(result.material.model)},
      {"sheen_form", toString(sheenFormOf(result))},
      {"choice", result.choiceReason},
      {"conventions",
       {{"frame", "z = surface normal, x = azimuth 0 of the Bonn grid (docs/method.md §1.2), azimuths "
                  "counter-clockwise"},
        {"tangent", "the axis of the larger GGX alpha (alpha_tangent >= alpha_bitangent), as "
                    "glTF KHR_materials_anisotropy's anisotropy direction; the lobe repeats every "
                    "180 deg"},
        {"roughness", "alpha convention: alpha = perceptual roughness^2"},
        {"brdf", brdfConvention(sheenFormOf(result))},
        {"sigma", "one standard deviation from the Jacobian at the solution, treating the misfit "
                  "as noise; null where the table does not determine the parameter"}}},
      {"parameters", parametersJson(result.material, result.sigmas)},
      {"metrics", metricsJson(result.metrics)},
      {"metrics_convention", "the fitted material tabulated on the Bonn grid against the table, "
                             "as slicecap compare TABLE FIT"},
      {"candidates", candidates},
  };
}

std::string materialJsonText(const json& document) { return document.dump(2) + "\n"; }

void writeMaterialJson(const std::filesystem::path& path, const json& document) {
  io::writeStreamReplacing(path, [&](std::ostream& out) { out << materialJsonText(document); });
}

}  // namespace slicecap::fit
