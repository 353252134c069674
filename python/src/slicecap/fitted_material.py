"""A material fitted by `slicecap fit` (docs/material-fit.md): its JSON read and checked, and its
BRDF evaluated in numpy, term for term as lib/fit (fitted_material.cpp, lobe_terms.hpp).

The evaluation is the reference the viewer's WebGL shader is tested against
(python/tests/test_viewer.py), in the table's frame (z = normal, x = the Bonn grid's azimuth 0,
the tangent at `tangent_deg` counter-clockwise from x):

    under = diffuse / pi + Schlick F(l.h) D_ggx G2_smith / (4 cos_i cos_v)
    base  = under                                 (no sheen)
    base  = sheen D_charlie V_charlie + under min(1 - s E(cos_v), 1 - s E(cos_i))
                                                  (sheen_form "khr_materials_sheen", version 2)
    base  = under + sheen D_charlie / (4 (cos_i + cos_v - cos_i cos_v))
                                                  (sheen_form "additive", every version-1 file)
    f_r   = base                                  (models "ggx", "ggx+sheen")
    f_r   = base (1 - w Fc) + w Fc coat           (models "ggx+coat", "ggx+sheen+coat")

The "khr_materials_sheen" form is glTF KHR_materials_sheen's layering: V_charlie its "Charlie"
visibility, s the largest sheen channel, E the sheen's directional albedo, tabulated by the same
quadrature as lib/fit sheen_albedo.cpp (sheen_albedo_table).

with the clear coat layered as glTF's KHR_materials_clearcoat (coat IOR 1.5): w = coat_weight,
Fc = 0.04 + 0.96 (1 - cos_v)^5 (the view's cosine with the normal, not l.h), and coat the
isotropic GGX lobe D G2 / (4 cos_i cos_v) of alpha coat_alpha, without Fresnel.
"""

import json
import math
import os
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from slicecap.abrdf_exr import SlicecapFileError
from slicecap.paths import StrPath

FORMAT = "slicecap-material"
FORMAT_VERSION = 2
# Version 1 has no "sheen_form": its sheen is the additive one.
FORMAT_VERSIONS = (1, 2)
SHEEN_FORMS = ("khr_materials_sheen", "additive")
MODELS = ("ggx", "ggx+sheen", "ggx+coat", "ggx+sheen+coat")
_RGB = ("diffuse_albedo", "specular_f0")
_SCALARS = ("specular_f90", "alpha_tangent", "alpha_bitangent", "tangent_deg")
_SHEEN_RGB, _SHEEN_SCALAR = "sheen_colour", "sheen_roughness"
_COAT_SCALARS = ("coat_weight", "coat_alpha")
# KHR_materials_clearcoat's coat: IOR 1.5, so its Schlick f0 is ((1.5 - 1) / (1.5 + 1))^2 = 0.04.
COAT_F0 = 0.04


# The albedo table's nodes (lib/fit sheen_albedo.hpp): cosines 0..1, roughness 0.05..1.
SHEEN_ALBEDO_COSINES, SHEEN_ALBEDO_ROUGHNESSES = 33, 39
SHEEN_ALBEDO_MIN_ROUGHNESS, SHEEN_ALBEDO_MAX_ROUGHNESS = 0.05, 1.0
_sheen_albedo_table: np.ndarray | None = None


def _charlie_l(x: ArrayLike, alpha: float) -> np.ndarray:
    """KHR_materials_sheen's l(x, alpha_g) of the Charlie visibility."""
    w = (1.0 - alpha) * (1.0 - alpha)

    def mix(a: float, b: float) -> float:
        return a + (b - a) * w

    a, b, c = mix(21.5473, 25.3245), mix(3.82987, 3.32435), mix(0.19823, 0.16801)
    d, e = mix(-1.97760, -1.27393), mix(-4.32054, -4.85967)
    xs = np.asarray(x, dtype=np.float64)
    power = np.where(xs > 0.0, np.exp(c * np.log(np.where(xs > 0.0, xs, 1.0))), 0.0)
    return np.asarray(a / (1.0 + b * power) + d * xs + e)


def charlie_lambda(cos_theta: ArrayLike, alpha: float) -> np.ndarray:
    """KHR_materials_sheen's lambda_sheen(cos_theta, alpha_g)."""
    cosines = np.asarray(cos_theta, dtype=np.float64)
    low = np.abs(cosines) < 0.5
    high = np.exp(2.0 * _charlie_l(0.5, alpha)
                  - _charlie_l(np.where(low, 0.5, 1.0 - cosines), alpha))
    return np.asarray(np.where(low, np.exp(_charlie_l(np.where(low, cosines, 0.25), alpha)), high))


def charlie_visibility(cos_l: ArrayLike, cos_v: ArrayLike, alpha: float) -> np.ndarray:
    """KHR_materials_sheen's sheen_visibility (the "Charlie" one)."""
    cl, cv = np.asarray(cos_l, dtype=np.float64), np.asarray(cos_v, dtype=np.float64)
    return 1.0 / ((1.0 + charlie_lambda(cv, alpha) + charlie_lambda(cl, alpha)) * (4.0 * cv * cl))


def sheen_albedo_table() -> np.ndarray:
    """(roughnesses, cosines) E(mu, r) = the hemisphere's integral of D_charlie V_charlie cos_l:
    a midpoint rule over theta_l (64 steps) and phi (64 steps over [0, pi], doubled), mu floored
    at 1e-3, as lib/fit sheen_albedo.cpp. Computed once."""
    global _sheen_albedo_table
    if _sheen_albedo_table is None:
        steps = 64
        theta = (np.arange(steps) + 0.5) * (math.pi / 2) / steps
        phi = (np.arange(steps) + 0.5) * math.pi / steps
        cos_l, sin_l = np.cos(theta)[:, None], np.sin(theta)[:, None]
        table = np.zeros((SHEEN_ALBEDO_ROUGHNESSES, SHEEN_ALBEDO_COSINES))
        step = ((SHEEN_ALBEDO_MAX_ROUGHNESS - SHEEN_ALBEDO_MIN_ROUGHNESS)
                / (SHEEN_ALBEDO_ROUGHNESSES - 1))
        for j in range(SHEEN_ALBEDO_ROUGHNESSES):
            alpha = SHEEN_ALBEDO_MIN_ROUGHNESS + j * step
            for i in range(SHEEN_ALBEDO_COSINES):
                mu = max(i / (SHEEN_ALBEDO_COSINES - 1), 1e-3)
                sin_v = math.sqrt(1.0 - mu * mu)
                visibility = 1.0 / ((1.0 + charlie_lambda(mu, alpha)
                                     + charlie_lambda(cos_l, alpha)) * (4.0 * mu * cos_l))
                hx, hy, hz = sin_l * np.cos(phi) + sin_v, sin_l * np.sin(phi), cos_l + mu
                cos_h = hz / np.sqrt(hx * hx + hy * hy + hz * hz)
                sin2h = np.maximum(1.0 - cos_h * cos_h, 0.0)
                d = (2.0 + 1.0 / alpha) * sin2h ** (0.5 / alpha) / (2.0 * math.pi)
                total = np.sum(d * visibility * cos_l * sin_l)
                table[j, i] = 2.0 * total * (math.pi / 2 / steps) * (math.pi / steps)
        _sheen_albedo_table = table
    return _sheen_albedo_table


def sheen_albedo(cos_theta: ArrayLike, roughness: float) -> np.ndarray:
    """E(cos_theta, r) from sheen_albedo_table: linear in the cosine, Catmull-Rom in r (held in
    the table's range), as lib/fit sheen_albedo.hpp."""
    table = sheen_albedo_table()
    mu = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0) * (SHEEN_ALBEDO_COSINES - 1)
    i = np.minimum(mu.astype(int), SHEEN_ALBEDO_COSINES - 2)
    f_mu = mu - i
    step = ((SHEEN_ALBEDO_MAX_ROUGHNESS - SHEEN_ALBEDO_MIN_ROUGHNESS)
            / (SHEEN_ALBEDO_ROUGHNESSES - 1))
    at = min(max((roughness - SHEEN_ALBEDO_MIN_ROUGHNESS) / step, 0.0),
             SHEEN_ALBEDO_ROUGHNESSES - 1.0)
    j = min(int(at), SHEEN_ALBEDO_ROUGHNESSES - 2)
    t = at - j

    def node(k: int) -> np.ndarray:
        row = table[min(max(k, 0), SHEEN_ALBEDO_ROUGHNESSES - 1)]
        return row[i] * (1.0 - f_mu) + row[i + 1] * f_mu

    p0, p1, p2, p3 = node(j - 1), node(j), node(j + 1), node(j + 2)
    t2, t3 = t * t, t * t * t
    return 0.5 * (2.0 * p1 + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2
                  + (3.0 * p1 - p0 - 3.0 * p2 + p3) * t3)


def has_sheen(model: str) -> bool:
    """Whether a model of MODELS carries the sheen term."""
    return "sheen" in model.split("+")


def has_coat(model: str) -> bool:
    """Whether a model of MODELS carries the clear coat (its name ends in "+coat")."""
    return model.endswith("+coat")


def ggx_lobe(light: np.ndarray, view: np.ndarray, half: np.ndarray, alpha_tangent: float,
             alpha_bitangent: float, tangent_deg: float) -> np.ndarray:
    """(...,) D_ggx(h) G2_smith(l, v) / (4 cos_i cos_v) of an anisotropic GGX lobe, no Fresnel
    (lib/fit lobe_terms.hpp); the clear coat is this lobe with both alphas equal."""
    t = math.radians(tangent_deg)
    cos_t, sin_t = math.cos(t), math.sin(t)

    def local(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return w[..., 0] * cos_t + w[..., 1] * sin_t, -w[..., 0] * sin_t + w[..., 1] * cos_t

    at2, ab2 = alpha_tangent**2, alpha_bitangent**2
    hx, hy = local(half)
    s = hx * hx / at2 + hy * hy / ab2 + half[..., 2] ** 2
    distribution = 1.0 / (math.pi * alpha_tangent * alpha_bitangent * s * s)

    def smith_lambda(w: np.ndarray) -> np.ndarray:
        wx, wy = local(w)
        return (np.sqrt(1.0 + (at2 * wx * wx + ab2 * wy * wy) / w[..., 2] ** 2) - 1.0) / 2.0

    return distribution / (
        (1.0 + smith_lambda(light) + smith_lambda(view)) * (4.0 * light[..., 2] * view[..., 2])
    )


@dataclass(frozen=True)
class FittedMaterial:
    """The parameters of docs/material-fit.md "The JSON" (values only, no sigmas)."""

    model: str
    diffuse_albedo: tuple[float, float, float]
    specular_f0: tuple[float, float, float]
    specular_f90: float
    alpha_tangent: float
    alpha_bitangent: float
    tangent_deg: float
    sheen_colour: tuple[float, float, float] = (0.0, 0.0, 0.0)
    sheen_roughness: float = 0.5
    # How the sheen joins the base: "khr_materials_sheen" (version 2's fits) or "additive".
    sheen_form: str = "khr_materials_sheen"
    # Read only for the "+coat" models; the defaults are what the other models leave unused.
    coat_weight: float = 0.0
    coat_alpha: float = 0.1

    def evaluate(self, to_light: np.ndarray, to_view: np.ndarray) -> np.ndarray:
        """(..., 3) RGB BRDF in 1/sr for (..., 3) unit vectors toward the light and the viewer in
        the table's frame; 0 where either is at or below the surface (z <= 0), where the fit's
        model is not defined."""
        light = np.asarray(to_light, dtype=np.float64)
        view = np.asarray(to_view, dtype=np.float64)
        above = (light[..., 2] > 0.0) & (view[..., 2] > 0.0)
        # Below-horizon pairs get a harmless stand-in so that no division warns; they are zeroed.
        light = np.where(above[..., None], light, [0.0, 0.0, 1.0])
        view = np.where(above[..., None], view, [0.0, 0.0, 1.0])
        half = light + view
        half = half / np.linalg.norm(half, axis=-1, keepdims=True)
        specular = ggx_lobe(light, view, half, self.alpha_tangent, self.alpha_bitangent,
                            self.tangent_deg)
        cos_i, cos_v = light[..., 2], view[..., 2]
        cos_lh = np.clip(np.sum(light * half, axis=-1), 0.0, 1.0)
        fresnel_weight = (1.0 - cos_lh) ** 5
        f0 = np.asarray(self.specular_f0)
        fresnel = f0 + (self.specular_f90 - f0) * fresnel_weight[..., None]
        value = np.asarray(self.diffuse_albedo) / math.pi + fresnel * specular[..., None]
        if has_sheen(self.model):
            inverse = 1.0 / self.sheen_roughness
            log_sin2 = np.log(np.maximum(1.0 - half[..., 2] ** 2, 1e-12))
            sheen = (2.0 + inverse) * np.exp(log_sin2 * 0.5 * inverse) / (2.0 * math.pi)
            if self.sheen_form == "khr_materials_sheen":
                sheen = sheen * charlie_visibility(cos_i, cos_v, self.sheen_roughness)
                albedo = np.maximum(sheen_albedo(cos_i, self.sheen_roughness),
                                    sheen_albedo(cos_v, self.sheen_roughness))
                scaling = 1.0 - max(self.sheen_colour) * albedo
                value = value * scaling[..., None]
            else:
                sheen = sheen / (4.0 * (cos_i + cos_v - cos_i * cos_v))
            value = value + np.asarray(self.sheen_colour) * sheen[..., None]
        if has_coat(self.model):
            # The coat's Fresnel takes the view's cosine, as KHR_materials_clearcoat: the layer
            # dims everything beneath it by what it reflects toward the viewer.
            coat_fresnel = self.coat_weight * (COAT_F0 + (1.0 - COAT_F0) * (1.0 - cos_v) ** 5)
            coat = ggx_lobe(light, view, half, self.coat_alpha, self.coat_alpha, 0.0)
            value = value * (1.0 - coat_fresnel[..., None]) + (coat_fresnel * coat)[..., None]
        return np.where(above[..., None], value, 0.0)


def _number(path: StrPath, name: str, raw: object, count: int) -> float | tuple[float, ...]:
    """A parameter's value: `count` finite numbers (count 1: one number)."""
    values: list[Any] = raw if isinstance(raw, list) else [raw]
    ok = len(values) == count and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
        for v in values
    )
    if not ok:
        what = f"{count} finite numbers" if count > 1 else "a finite number"
        raise SlicecapFileError(
            f"{os.fspath(path)}: not a completed slicecap fit: parameter {name} must be {what}, "
            f"got {raw!r}"
        )
    return tuple(float(v) for v in values) if count > 1 else float(values[0])


def parse_fitted_material(document: object, path: StrPath) -> FittedMaterial:
    """The material of a parsed `slicecap fit` JSON. Raises SlicecapFileError naming `path` for
    anything but a completed fit (another format or version, an unknown model, a missing or
    non-finite parameter, one outside its range, no metrics.delta_e), as `slicecap fit
    MATERIAL.json --gltf ...` refuses them."""

    def refuse(what: str) -> SlicecapFileError:
        return SlicecapFileError(f"{os.fspath(path)}: not a completed slicecap fit: {what}")

    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise refuse(f'"format" is not "{FORMAT}"')
    version = document.get("format_version")
    if isinstance(version, bool) or version not in FORMAT_VERSIONS:
        raise refuse(f'"format_version" {version!r} is not one of {FORMAT_VERSIONS}')
    sheen_form = "additive"
    if version == 2:
        form = document.get("sheen_form")
        if not isinstance(form, str) or form not in SHEEN_FORMS:
            raise refuse(f'"sheen_form" {form!r} is not one of {", ".join(SHEEN_FORMS)}')
        sheen_form = form
    model = document.get("model")
    if model not in MODELS:
        raise refuse(f'"model" {model!r} is not one of {", ".join(MODELS)}')
    parameters = document.get("parameters")
    if not isinstance(parameters, dict):
        raise refuse('no "parameters" object')
    wanted = [(n, 3) for n in _RGB] + [(n, 1) for n in _SCALARS]
    if has_sheen(model):
        wanted += [(_SHEEN_RGB, 3), (_SHEEN_SCALAR, 1)]
    if has_coat(model):
        wanted += [(n, 1) for n in _COAT_SCALARS]
    # Each value checked by _number: RGB ones tuples of three floats, the others floats.
    values: dict[str, Any] = {}
    for name, count in wanted:
        entry = parameters.get(name)
        if not isinstance(entry, dict) or "value" not in entry:
            raise refuse(f"parameter {name} is missing")
        values[name] = _number(path, name, entry["value"], count)
    # The ranges `slicecap fit` keeps to and its exports check (docs/material-export.md).
    ranges = {"diffuse_albedo": (0.0, math.inf), "specular_f0": (0.0, 1.0),
              "specular_f90": (0.0, 1.0),
              _SHEEN_RGB: (0.0, 1.0 if sheen_form == "khr_materials_sheen" else math.inf),
              "coat_weight": (0.0, 1.0)}
    for name, (low, high) in ranges.items():
        if name in values:
            for v in values[name] if isinstance(values[name], tuple) else (values[name],):
                if not low <= v <= high:
                    raise refuse(f"parameter {name} must be in [{low:g}, {high:g}], got {v!r}")
    for name in ("alpha_tangent", "alpha_bitangent") + (
        (_SHEEN_SCALAR,) if has_sheen(model) else ()
    ) + (("coat_alpha",) if has_coat(model) else ()):
        if not values[name] > 0.0:
            raise refuse(f"parameter {name} must be positive, got {values[name]!r}")
    metrics = document.get("metrics")
    delta_e = metrics.get("delta_e") if isinstance(metrics, dict) else None
    if not isinstance(delta_e, (int, float)) or isinstance(delta_e, bool):
        raise refuse('no "metrics": {"delta_e": ...} (a fit that did not finish)')
    if (has_sheen(model) and sheen_form == "khr_materials_sheen"
            and values[_SHEEN_SCALAR] < SHEEN_ALBEDO_MIN_ROUGHNESS):
        raise refuse(f"parameter {_SHEEN_SCALAR} must be at least {SHEEN_ALBEDO_MIN_ROUGHNESS:g} "
                     f"in the khr_materials_sheen form, got {values[_SHEEN_SCALAR]!r}")
    return FittedMaterial(model=model, sheen_form=sheen_form, **values)


def read_fit_document(path: StrPath) -> tuple[FittedMaterial, dict]:
    """The material in a `slicecap fit` JSON file and the whole parsed document (for its metrics
    and choice); SlicecapFileError naming the file when it cannot be read, is not JSON, or is not
    a completed fit."""
    try:
        with open(os.fspath(path), encoding="utf-8") as file:
            text = file.read()
    except OSError as e:
        raise SlicecapFileError(f"{os.fspath(path)}: cannot read: {e.strerror}") from e
    except UnicodeDecodeError as e:
        raise SlicecapFileError(f"{os.fspath(path)}: not a text (UTF-8) file") from e
    try:
        document = json.loads(text)
    except json.JSONDecodeError as e:
        raise SlicecapFileError(f"{os.fspath(path)}: not JSON ({e.msg} at line {e.lineno})") from e
    return parse_fitted_material(document, path), document


def read_fitted_material(path: StrPath) -> FittedMaterial:
    """The material in a `slicecap fit` JSON file (read_fit_document, without the document)."""
    return read_fit_document(path)[0]
