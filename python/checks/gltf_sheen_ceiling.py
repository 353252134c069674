"""How near any glTF sheen can come to a fit's additive sheen (issue 46, "Sheen"): starting from a
.gltf's factors, a Nelder-Mead search over sheenColorFactor, sheenRoughnessFactor and
baseColorFactor (each clamped to [0, 1]) for the smallest `slicecap compare` dE of the glTF
material, evaluated by the specification (python/checks/gltf_spec_brdf.py, Charlie visibility),
against the fit's own table (`slicecap generate MATERIAL.json`). Everything else stays as
exported. A bound for any export-time compensation of the fit's sheen form:

    .venv/bin/python python/checks/gltf_sheen_ceiling.py M.gltf FIT.exr [--iterations 250]
"""

import argparse
import copy
import json
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from gltf_spec_brdf import REPOSITORY, gltf_brdf  # noqa: E402

sys.path.insert(0, str(REPOSITORY / "python" / "src"))
from slicecap.abrdf_exr import read_abrdf_exr  # noqa: E402
from slicecap.grid import GRID_DIRECTIONS_DEG, tabulate  # noqa: E402
from slicecap.image_metrics import _lab, srgb_encode  # noqa: E402


def mean_delta_e(reference: np.ndarray, test: np.ndarray) -> float:
    """`slicecap compare`'s mean dE: both times cos(theta_i), over the reference's maximum,
    8-bit sRGB, CIE76."""
    cosines = np.cos(np.radians(GRID_DIRECTIONS_DEG[:, 0]))[:, None, None]
    peak = (reference * cosines).max()

    def lab(table: np.ndarray) -> np.ndarray:
        return _lab(np.round(srgb_encode(np.clip(table * cosines / peak, 0, 1)) * 255))

    return float(np.linalg.norm(lab(reference) - lab(test), axis=-1).mean())


def search(material: dict, fit_table: np.ndarray, iterations: int) -> tuple[float, np.ndarray]:
    def factors(x: np.ndarray) -> dict:
        x = np.clip(x, 0.0, 1.0)
        m = copy.deepcopy(material)
        m["extensions"]["KHR_materials_sheen"] = {"sheenColorFactor": list(x[0:3]),
                                                  "sheenRoughnessFactor": max(x[3], 0.05)}
        m["pbrMetallicRoughness"]["baseColorFactor"] = list(x[4:7]) + [1.0]
        return m

    def cost(x: np.ndarray) -> float:
        return mean_delta_e(fit_table, tabulate(gltf_brdf(factors(x))).astype(float))

    sheen = material["extensions"]["KHR_materials_sheen"]
    start = np.array(sheen["sheenColorFactor"] + [sheen["sheenRoughnessFactor"]]
                     + material["pbrMetallicRoughness"]["baseColorFactor"][:3], dtype=float)
    simplex = [start] + [start + 0.05 * e for e in np.eye(start.size)]
    values = [cost(x) for x in simplex]
    for _ in range(iterations):
        order = np.argsort(values)
        simplex, values = [simplex[i] for i in order], [values[i] for i in order]
        centre = np.mean(simplex[:-1], axis=0)
        reflected = centre + (centre - simplex[-1])
        fr = cost(reflected)
        if fr < values[0]:
            expanded = centre + 2 * (centre - simplex[-1])
            fe = cost(expanded)
            simplex[-1], values[-1] = (expanded, fe) if fe < fr else (reflected, fr)
        elif fr < values[-2]:
            simplex[-1], values[-1] = reflected, fr
        else:
            contracted = centre + 0.5 * (simplex[-1] - centre)
            fc = cost(contracted)
            if fc < values[-1]:
                simplex[-1], values[-1] = contracted, fc
            else:
                simplex = [simplex[0]] + [simplex[0] + 0.5 * (x - simplex[0]) for x in simplex[1:]]
                values = [values[0]] + [cost(x) for x in simplex[1:]]
    best = int(np.argmin(values))
    return values[best], np.clip(simplex[best], 0.0, 1.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("gltf", type=pathlib.Path)
    parser.add_argument("fit_table", type=pathlib.Path)
    parser.add_argument("--iterations", type=int, default=250)
    args = parser.parse_args()
    material = json.loads(args.gltf.read_text())["materials"][0]
    fit_table = read_abrdf_exr(args.fit_table).values.astype(float)
    start = mean_delta_e(fit_table, tabulate(gltf_brdf(material)).astype(float))
    best, x = search(material, fit_table, args.iterations)
    print(f"as exported: dE {start:.2f}; best found: dE {best:.2f} with sheenColorFactor "
          f"{np.round(x[0:3], 3).tolist()}, sheenRoughnessFactor {x[3]:.3f}, baseColorFactor "
          f"{np.round(x[4:7], 3).tolist()}")


if __name__ == "__main__":
    main()
