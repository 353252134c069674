"""Shared by python/tests/test_material_export.py and python/bench/material_export_figures.py: the
fitted material's BRDF as docs/material-fit.md writes it, and the ratio of a Mitsuba snippet's BSDF
to it at random light/view pairs."""

import re

import numpy as np

from slicecap.fitted_material import sheen_albedo
from slicecap.grid import GRID_DIRECTIONS_DEG, to_unit_vectors


def khr_sheen_rest_scaling(parameters: dict) -> float:
    """What the Mitsuba snippet dims the diffuse + GGX of a khr_materials_sheen fit by
    (docs/material-export.md, Mitsuba): KHR_materials_sheen's 1 - max(sheen) max(E(cos_l),
    E(cos_v)) averaged over the 81 x 81 grid pairs with weight cos_l."""
    colour = max(parameters["sheen_colour"]["value"])
    roughness = parameters["sheen_roughness"]["value"]
    cosines = to_unit_vectors(GRID_DIRECTIONS_DEG)[:, 2]
    albedo = sheen_albedo(cosines, roughness)
    pair = np.maximum(albedo[:, None], albedo[None, :])  # light x view
    weight = np.repeat(cosines[:, None], len(cosines), axis=1)
    return float(np.sum(weight * (1.0 - colour * pair)) / np.sum(weight))


def fitted_brdf(parameters: dict, to_light: np.ndarray, to_view: np.ndarray) -> np.ndarray:
    """The fitted material's diffuse + GGX terms (no sheen) for unit vectors, z = normal."""
    p = {k: v["value"] for k, v in parameters.items()}
    half = to_light + to_view
    half = half / np.linalg.norm(half)
    t = np.radians(p["tangent_deg"])
    along, across = np.array([np.cos(t), np.sin(t), 0.0]), np.array([-np.sin(t), np.cos(t), 0.0])
    at, ab = p["alpha_tangent"], p["alpha_bitangent"]

    def lam(w):
        return (np.sqrt(1 + ((at * w @ along) ** 2 + (ab * w @ across) ** 2) / w[2] ** 2) - 1) / 2

    s = (half @ along / at) ** 2 + (half @ across / ab) ** 2 + half[2] ** 2
    d = 1 / (np.pi * at * ab * s * s)
    g = 1 / (1 + lam(to_light) + lam(to_view))
    f0 = np.array(p["specular_f0"])
    f = f0 + (p["specular_f90"] - f0) * (1 - to_light @ half) ** 5
    return np.array(p["diffuse_albedo"]) / np.pi + f * d * g / (4 * to_light[2] * to_view[2])


def ggx_stand_in(alpha: float, to_light: np.ndarray, to_view: np.ndarray) -> float:
    """Mitsuba's roughconductor of Fresnel 1 (material "none"), isotropic GGX with the separable
    Smith masking, per unit reflectance: the sheen's stand-in in a snippet
    (docs/material-export.md)."""
    half = to_light + to_view
    c2 = (half[2] / np.linalg.norm(half)) ** 2
    d = 1 / (np.pi * alpha**2 * c2 * c2 * (1 + (1 - c2) / (c2 * alpha**2)) ** 2)

    def g1(w):
        return 2 / (1 + np.sqrt(1 + alpha**2 * (1 - w[2] ** 2) / w[2] ** 2))

    return d * g1(to_light) * g1(to_view) / (4 * to_light[2] * to_view[2])


def sheen_stand_in(snippet: str):
    """The BRDF the snippet adds for the fit's sheen, f(to_light, to_view) -> RGB, from its own
    blend weight, alpha and specular_reflectance; None for a snippet without a stand-in."""
    if 'name="specular_reflectance"' not in snippet:
        return None

    def value(name):
        found = re.search(f'name="{name}" value="([^"]+)"', snippet)[1]
        return np.array([float(v) for v in found.split(",")])

    weight, alpha = value("weight")[0], value("alpha")[0]
    reflectance = value("specular_reflectance")
    return lambda to_light, to_view: weight * reflectance * ggx_stand_in(alpha, to_light, to_view)


def mitsuba_ratios(mi, scene, parameters: dict, pairs=300, max_theta_deg=75.0, seed=7,
                   extra=None, rest_scale=1.0):
    """Mitsuba's BSDF of the snippet's sample shape (its eval / cos) over the fitted BRDF, per
    channel, at `pairs` random light/view pairs up to `max_theta_deg`, in world directions on the
    turned rectangle: a wrong tangent rotation shows as ratios far from 1. `extra(to_light,
    to_view)`, when given, is added to the fitted BRDF (a term the snippet should also have), whose
    diffuse + GGX is multiplied by `rest_scale`."""
    bsdf = scene.shapes()[0].bsdf()
    si = scene.ray_intersect(mi.Ray3f([0.01, 0.02, 1.0], [0.0, 0.0, -1.0]))
    rng = np.random.default_rng(seed)
    ratios = []
    for _ in range(pairs):
        theta = np.radians(rng.uniform(0, max_theta_deg, 2))
        phi = rng.uniform(0, 2 * np.pi, 2)
        to_light, to_view = np.stack(
            [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], 1)
        si.wi = si.to_local(mi.Vector3f(*to_view))
        value = np.array(bsdf.eval(mi.BSDFContext(), si, si.to_local(mi.Vector3f(*to_light))))
        expected = rest_scale * fitted_brdf(parameters, to_light, to_view)
        if extra is not None:
            expected = expected + extra(to_light, to_view)
        ratios.append(value / to_light[2] / expected)
    return np.array(ratios)
