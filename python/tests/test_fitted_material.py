"""The clear coat of slicecap.fitted_material (models "ggx+coat", "ggx+sheen+coat"): glTF
KHR_materials_clearcoat's layering checked against values worked out here from the formulas, not
from the module's code; a coat of weight 0 is the base model; the reader refuses a missing or
out-of-range coat parameter naming the file and the parameter. The sheen of format version 2
("khr_materials_sheen") against python/checks/gltf_spec_brdf.py, and version 1's additive sheen."""

import json
import math
import pathlib
import sys

import numpy as np
import pytest
from brdf_pairs import random_pairs

from slicecap.abrdf_exr import SlicecapFileError
from slicecap.fitted_material import MODELS, FittedMaterial, read_fitted_material

BASE = FittedMaterial("ggx", (0.2, 0.02, 0.02), (0.5, 0.1, 0.1), 0.8, 0.45, 0.2, 70.0)
SHEEN_BASE = FittedMaterial(
    "ggx+sheen", (0.15, 0.01, 0.02), (0.02, 0.03, 0.04), 0.4, 0.3, 0.12, 37.0,
    sheen_colour=(0.7, 0.15, 0.15), sheen_roughness=0.3, sheen_form="additive",
)


def coated(base: FittedMaterial, weight: float, alpha: float) -> FittedMaterial:
    return FittedMaterial(**{**base.__dict__, "model": base.model + "+coat",
                             "coat_weight": weight, "coat_alpha": alpha})


def unit(theta_deg: float, phi_deg: float) -> np.ndarray:
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


@pytest.mark.parametrize("base", [BASE, SHEEN_BASE], ids=["ggx", "ggx+sheen"])
def test_a_coat_of_weight_zero_is_the_base_model(base):
    lights, views = random_pairs(500, seed=7)
    np.testing.assert_array_equal(coated(base, 0.0, 0.05).evaluate(lights, views),
                                  base.evaluate(lights, views))


def isotropic_ggx_coat(alpha_c: float, light: np.ndarray, view: np.ndarray) -> float:
    """D G2 / (4 cos_i cos_v) of an isotropic GGX lobe, D written in its cos(theta_h) form
    a^2 / (pi (cos^2 theta_h (a^2 - 1) + 1)^2) and Lambda in its tan(theta) form: not the
    module's half-vector-in-the-tangent-frame expressions."""
    half = (light + view) / np.linalg.norm(light + view)
    a2 = alpha_c * alpha_c
    d = a2 / (math.pi * (half[2] ** 2 * (a2 - 1.0) + 1.0) ** 2)

    def smith_lambda(w: np.ndarray) -> float:
        tan2 = (1.0 - w[2] ** 2) / w[2] ** 2
        return (math.sqrt(1.0 + a2 * tan2) - 1.0) / 2.0

    g2 = 1.0 / (1.0 + smith_lambda(light) + smith_lambda(view))
    return d * g2 / (4.0 * light[2] * view[2])


# (light, view): both along the normal (Fc = 0.04, D = 1 / (pi a^2), G2 = 1); a mirror pair at
# 60 deg; and the light along the normal with the view at 60 deg, where l.h (cos 30 deg) and the
# view's cosine (0.5) give Fresnel weights 0.0400 and 0.0700: only the view's is KHR's.
PAIRS = {
    "normal": (unit(0.0, 0.0), unit(0.0, 0.0)),
    "mirror-60": (unit(60.0, 20.0), unit(60.0, 200.0)),
    "off-mirror": (unit(0.0, 0.0), unit(60.0, 135.0)),
}


@pytest.mark.parametrize("pair", PAIRS, ids=list(PAIRS))
@pytest.mark.parametrize("base", [BASE, SHEEN_BASE], ids=["ggx", "ggx+sheen"])
def test_the_coat_layers_as_gltf_clearcoat(base, pair):
    light, view = PAIRS[pair]
    weight, alpha_c = 0.7, 0.08
    coat_fresnel = 0.04 + 0.96 * (1.0 - view[2]) ** 5
    base_value = base.evaluate(light, view)
    expected = (base_value * (1.0 - weight * coat_fresnel)
                + weight * coat_fresnel * isotropic_ggx_coat(alpha_c, light, view))
    got = coated(base, weight, alpha_c).evaluate(light, view)
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    # The coat must be seen at all: it moves the value by more than the tolerance above.
    assert np.max(np.abs(got / base_value - 1.0)) > 1e-3
    if pair == "normal":
        # At normal incidence and view: 0.04 w / (4 pi a^2) added, the base times (1 - 0.04 w).
        np.testing.assert_allclose(
            got, base_value * (1 - 0.04 * weight) + 0.04 * weight / (4 * math.pi * alpha_c**2),
            rtol=1e-12)


def fit_json(model: str, **overrides) -> dict:
    """A completed `slicecap fit` JSON (the fields the reader checks) of `model`; overrides
    replace parameters' values, None drops the parameter."""
    values: dict = {"diffuse_albedo": [0.2, 0.02, 0.02], "specular_f0": [0.5, 0.1, 0.1],
                    "specular_f90": 0.8, "alpha_tangent": 0.45, "alpha_bitangent": 0.2,
                    "tangent_deg": 70.0}
    if "sheen" in model:
        values |= {"sheen_colour": [0.7, 0.15, 0.15], "sheen_roughness": 0.3}
    if model.endswith("+coat"):
        values |= {"coat_weight": 0.7, "coat_alpha": 0.08}
    values |= overrides
    parameters = {n: {"value": v, "sigma": None, "unit": "-"} for n, v in values.items()
                  if v is not None}
    return {"format": "slicecap-material", "format_version": 1, "source": "t.exr",
            "model": model, "parameters": parameters, "metrics": {"delta_e": 0.5}}


def test_the_reader_takes_the_coat_models(tmp_path):
    assert {"ggx+coat", "ggx+sheen+coat"} <= set(MODELS)
    for model in ("ggx+coat", "ggx+sheen+coat"):
        path = tmp_path / "fit.json"
        path.write_text(json.dumps(fit_json(model, coat_weight=0.35, coat_alpha=0.012)))
        material = read_fitted_material(path)
        assert (material.model, material.coat_weight, material.coat_alpha) == (model, 0.35, 0.012)
        assert material.sheen_roughness == (0.3 if "sheen" in model else 0.5)


@pytest.mark.parametrize(
    "model,overrides,message",
    [
        ("ggx+coat", {"coat_weight": None}, "parameter coat_weight is missing"),
        ("ggx+coat", {"coat_alpha": None}, "parameter coat_alpha is missing"),
        ("ggx+sheen+coat", {"coat_alpha": None}, "parameter coat_alpha is missing"),
        ("ggx+sheen+coat", {"sheen_colour": None}, "parameter sheen_colour is missing"),
        ("ggx+coat", {"coat_weight": 1.2}, "parameter coat_weight must be in [0, 1], got 1.2"),
        ("ggx+coat", {"coat_weight": -0.1}, "parameter coat_weight must be in [0, 1], got -0.1"),
        ("ggx+coat", {"coat_weight": [0.5, 0.5, 0.5]},
         "parameter coat_weight must be a finite number"),
        ("ggx+coat", {"coat_alpha": 0.0}, "parameter coat_alpha must be positive, got 0.0"),
        ("ggx+coat", {"coat_alpha": -0.05}, "parameter coat_alpha must be positive"),
        ("ggx+sheen+coat", {"coat_weight": "0.5"},
         "parameter coat_weight must be a finite number"),
        ("ggx+coats", {}, "\"model\" 'ggx+coats' is not one of"),
    ],
    ids=["no-weight", "no-alpha", "sheen-no-alpha", "sheen-no-colour", "weight-above-1",
         "weight-negative", "weight-rgb", "alpha-zero", "alpha-negative", "weight-string",
         "unknown-model"],
)
def test_the_reader_refuses_a_bad_coat_naming_file_and_field(tmp_path, model, overrides,
                                                             message):
    path = tmp_path / "coat.json"
    path.write_text(json.dumps(fit_json(model, **overrides)))
    with pytest.raises(SlicecapFileError) as error:
        read_fitted_material(path)
    assert str(error.value).startswith(f"{path}: not a completed slicecap fit: ")
    assert message in str(error.value), str(error.value)


# ---- the sheen in KHR_materials_sheen's layering (format version 2's "khr_materials_sheen") ----

KHR_VELVET = FittedMaterial("ggx+sheen", (0.12, 0.02, 0.03), (0.0, 0.0, 0.0), 0.0, 0.3, 0.3, 0.0,
                            sheen_colour=(0.8, 0.2, 0.25), sheen_roughness=0.36)


def test_the_khr_sheen_is_the_extensions_layering_by_the_specifications_evaluator():
    """python/checks/gltf_spec_brdf.py, written from the Khronos texts alone, evaluates the glTF
    material with the same factors (no specular, base colour = albedo, sheen colour, roughness
    factor sqrt(r)): only the two quadratures of E differ."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "checks"))
    from gltf_spec_brdf import gltf_brdf

    gltf = {"pbrMetallicRoughness": {"baseColorFactor": [*KHR_VELVET.diffuse_albedo, 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": 0.0},
                           "KHR_materials_sheen": {
                               "sheenColorFactor": list(KHR_VELVET.sheen_colour),
                               "sheenRoughnessFactor": math.sqrt(KHR_VELVET.sheen_roughness)}}}
    lights = np.array([unit(t, p) for t in (0, 30, 60, 75) for p in (0, 90, 200)])
    views = np.array([unit(t, p) for t in (15, 45, 75) for p in (10, 180, 300)])
    light, view = (np.repeat(lights, len(views), 0), np.tile(views, (len(lights), 1)))
    expected = gltf_brdf(gltf)(light, view)
    np.testing.assert_allclose(KHR_VELVET.evaluate(light, view), expected, rtol=5e-3)
    additive = FittedMaterial(**{**KHR_VELVET.__dict__, "sheen_form": "additive"})
    assert np.max(np.abs(additive.evaluate(light, view) / expected - 1)) > 0.05


def test_the_reader_takes_the_sheen_form_of_version_2_and_version_1s_additive_sheen(tmp_path):
    path = tmp_path / "fit.json"
    document = fit_json("ggx+sheen")
    path.write_text(json.dumps(document))
    assert read_fitted_material(path).sheen_form == "additive"
    document |= {"format_version": 2, "sheen_form": "khr_materials_sheen"}
    path.write_text(json.dumps(document))
    assert read_fitted_material(path).sheen_form == "khr_materials_sheen"
    for form, message in ((None, "\"sheen_form\" None"), ("charlie", "\"sheen_form\" 'charlie'")):
        document["sheen_form"] = form
        path.write_text(json.dumps(document))
        with pytest.raises(SlicecapFileError, match=message):
            read_fitted_material(path)
    document["sheen_form"] = "khr_materials_sheen"
    document["parameters"]["sheen_colour"]["value"] = [1.2, 0.1, 0.1]
    path.write_text(json.dumps(document))
    with pytest.raises(SlicecapFileError, match="sheen_colour must be in"):
        read_fitted_material(path)
