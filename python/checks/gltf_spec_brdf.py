"""glTF's BRDF of the material in a .gltf file, evaluated by the Khronos specifications' formulas
(glTF 2.0 Appendix B; KHR_materials_anisotropy, _specular, _ior, _sheen and _clearcoat READMEs,
"Implementation"), written from those texts alone: a second evaluator beside the C++ one in
lib/material_export/src/gltf_brdf.cpp, sharing no code with it or with the exporter. Measures an
export against the fit's own table (`slicecap generate MATERIAL.json`):

    .venv/bin/python python/checks/gltf_spec_brdf.py M.gltf FIT.exr [--slicecap build/app/slicecap]
        [--sheen-visibility charlie|ashikhmin]

prints `slicecap compare FIT.exr GLTF.exr`'s mean dE of the glTF table against the fit's.
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPOSITORY / "python" / "src"))
from slicecap.abrdf_exr import write_abrdf_exr  # noqa: E402
from slicecap.grid import tabulate  # noqa: E402


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.sum(a * b, axis=-1)


def _factors(material: dict) -> dict:
    """The factors with the specifications' defaults where the file leaves them out."""
    pbr = material.get("pbrMetallicRoughness", {})
    ext = material.get("extensions", {})
    aniso = ext.get("KHR_materials_anisotropy", {})
    spec = ext.get("KHR_materials_specular", {})
    sheen = ext.get("KHR_materials_sheen", {})
    coat = ext.get("KHR_materials_clearcoat", {})
    return {
        "base": np.array(pbr.get("baseColorFactor", [1, 1, 1, 1])[:3], dtype=float),
        "metallic": pbr.get("metallicFactor", 1.0),
        "roughness": pbr.get("roughnessFactor", 1.0),
        "strength": aniso.get("anisotropyStrength", 0.0),
        "rotation": aniso.get("anisotropyRotation", 0.0),
        "specular": spec.get("specularFactor", 1.0),
        "specular_color": np.array(spec.get("specularColorFactor", [1, 1, 1]), dtype=float),
        "ior": ext.get("KHR_materials_ior", {}).get("ior", 1.5),
        "sheen_color": np.array(sheen.get("sheenColorFactor", [0, 0, 0]), dtype=float),
        "sheen_roughness": sheen.get("sheenRoughnessFactor", 0.0),
        "clearcoat": coat.get("clearcoatFactor", 0.0),
        "clearcoat_roughness": coat.get("clearcoatRoughnessFactor", 0.0),
    }


def _ggx(light, view, h, t, b, at, ab):
    """KHR_materials_anisotropy's D_GGX_anisotropic x V_GGX_anisotropic (no clamp of V)."""
    a2 = at * ab
    f = np.stack([ab * _dot(t, h), at * _dot(b, h), a2 * h[:, 2]], -1)
    w2 = a2 / _dot(f, f)
    d = a2 * w2 * w2 / np.pi

    def length(w):
        return np.linalg.norm(np.stack([at * _dot(t, w), ab * _dot(b, w), w[:, 2]], -1), axis=-1)

    return d * 0.5 / (light[:, 2] * length(view) + view[:, 2] * length(light))


def _sheen_l(x, alpha_g):
    w = (1 - alpha_g) ** 2
    a = 21.5473 * (1 - w) + 25.3245 * w
    b = 3.82987 * (1 - w) + 3.32435 * w
    c = 0.19823 * (1 - w) + 0.16801 * w
    d = -1.97760 * (1 - w) + -1.27393 * w
    e = -4.32054 * (1 - w) + -4.85967 * w
    return a / (1 + b * x**c) + d * x + e


def _lambda_sheen(cos_theta, alpha_g):
    return np.where(np.abs(cos_theta) < 0.5, np.exp(_sheen_l(cos_theta, alpha_g)),
                    np.exp(2 * _sheen_l(0.5, alpha_g) - _sheen_l(1 - cos_theta, alpha_g)))


def _sheen_brdf(n_l, n_v, n_h, roughness, visibility):
    alpha_g = max(roughness * roughness, 1e-7)
    inv_r = 1 / alpha_g
    d = (2 + inv_r) * np.maximum(1 - n_h * n_h, 0) ** (inv_r * 0.5) / (2 * np.pi)
    if visibility == "charlie":
        vis = 1 / ((1 + _lambda_sheen(n_v, alpha_g) + _lambda_sheen(n_l, alpha_g))
                   * (4 * n_v * n_l))
    else:
        vis = 1 / (4 * (n_l + n_v - n_l * n_v))
    return d * vis


def sheen_albedo(roughness: float, visibility: str, cosines: np.ndarray) -> np.ndarray:
    """E(mu) = the sheen's D V cos integrated over the hemisphere (midpoint rule, 64 x 128)."""
    theta = (np.arange(64) + 0.5) * (np.pi / 2) / 64
    phi = (np.arange(128) + 0.5) * 2 * np.pi / 128
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    light = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1)
    light = light.reshape(-1, 3)
    out = []
    for mu in np.maximum(cosines, 1e-3):
        view = np.array([np.sqrt(1 - mu * mu), 0.0, mu])
        h = light + view
        h = h / np.linalg.norm(h, axis=-1, keepdims=True)
        f = _sheen_brdf(light[:, 2], mu, h[:, 2], roughness, visibility)
        out.append(np.sum(f * light[:, 2] * np.sin(th).reshape(-1))
                   * (np.pi / 2 / 64) * (2 * np.pi / 128))
    return np.array(out)


def gltf_brdf(material: dict, visibility: str = "charlie"):
    """f(to_light, to_view) -> RGB for (N, 3) unit vectors in the frame TANGENT = x, bitangent =
    y, normal = z."""
    f = _factors(material)
    rot = f["rotation"]
    t = np.array([np.cos(rot), np.sin(rot), 0.0])
    b = np.array([-np.sin(rot), np.cos(rot), 0.0])
    alpha = f["roughness"] ** 2
    at = max(alpha + (1 - alpha) * f["strength"] ** 2, 1e-7)
    ab = max(alpha, 1e-7)
    sheen_max = float(np.max(f["sheen_color"]))
    grid = np.linspace(0, 1, 65)
    albedo = sheen_albedo(f["sheen_roughness"], visibility, grid) if sheen_max > 0 else None

    def brdf(light: np.ndarray, v: np.ndarray) -> np.ndarray:
        h = light + v
        h = h / np.linalg.norm(h, axis=-1, keepdims=True)
        spec = _ggx(light, v, h, t, b, at, ab)[:, None]
        w = ((1 - np.abs(_dot(v, h))) ** 5)[:, None]
        f0_ior = ((f["ior"] - 1) / (f["ior"] + 1)) ** 2
        f0 = np.minimum(f0_ior * f["specular_color"], 1.0) * f["specular"]
        fresnel = f0 + (f["specular"] - f0) * w
        diffuse = f["base"] / np.pi
        dielectric = fresnel * spec + (1 - fresnel.max(axis=-1, keepdims=True)) * diffuse
        metal = spec * (f["base"] + (1 - f["base"]) * w)
        material_ = dielectric * (1 - f["metallic"]) + metal * f["metallic"]
        if albedo is not None:
            e_v = np.interp(v[:, 2], grid, albedo)
            e_l = np.interp(light[:, 2], grid, albedo)
            scaling = np.minimum(1 - sheen_max * e_v, 1 - sheen_max * e_l)[:, None]
            sheen = _sheen_brdf(light[:, 2], v[:, 2], h[:, 2], f["sheen_roughness"], visibility)
            material_ = f["sheen_color"] * sheen[:, None] + material_ * scaling
        if f["clearcoat"] > 0:
            fc = (0.04 + 0.96 * (1 - np.abs(v[:, 2])) ** 5)[:, None] * f["clearcoat"]
            ca = max(f["clearcoat_roughness"] ** 2, 1e-7)
            coat = _ggx(light, v, h, t, b, ca, ca)[:, None]
            material_ = material_ * (1 - fc) + coat * fc
        return material_

    return brdf


def gltf_versus_fit_delta_e(gltf: pathlib.Path, fit_table: pathlib.Path, slicecap: str,
                            visibility: str = "charlie") -> float:
    """`slicecap compare FIT GLTF`'s mean dE of the .gltf's first material, tabulated by the
    specifications, against the fit's table."""
    material = json.loads(gltf.read_text())["materials"][0]
    table = tabulate(gltf_brdf(material, visibility))
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "gltf.exr"
        write_abrdf_exr(out, table)
        run = subprocess.run([slicecap, "compare", str(fit_table), str(out), "--json"],
                             check=True, capture_output=True, text=True)
    return float(json.loads(run.stdout)["delta_e"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("gltf", type=pathlib.Path)
    parser.add_argument("fit_table", type=pathlib.Path)
    parser.add_argument("--slicecap", default=str(REPOSITORY / "build/app/slicecap"))
    parser.add_argument("--sheen-visibility", choices=["charlie", "ashikhmin"], default="charlie")
    args = parser.parse_args()
    delta_e = gltf_versus_fit_delta_e(args.gltf, args.fit_table, args.slicecap,
                                      args.sheen_visibility)
    print(f"{delta_e:.2f}")


if __name__ == "__main__":
    main()
