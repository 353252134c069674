"""The fitted material rendered exactly, in the consumer check's scene (consumer_scene.py), to split
a three.js figure against "Mitsuba's tabulated fit" into the reference's own interpolation (the
fit on the 81 x 81 grid, read by the slicecap plugin's linear taps) and what three.js adds.

A ray per pixel centre meets the analytic sphere of the glTF's sphere node (r 0.5); the tangent is
the nearest vertex's glTF TANGENT made perpendicular to the normal; the radiance is the fit's BRDF
(slicecap.fitted_material, the table's frame: x on the tangent) x the point light's intensity x
cos / d^2, as Mitsuba's direct integrator and three.js's punctual light. Checked on the same scene
against Mitsuba's exact render of the analytic model behind the table (the `truth` render): the
row "numpy exact vs Mitsuba truth" must be small for the other rows to mean anything.

    .venv/bin/python python/checks/exact_fit_render.py --consumer-out DIR [NAME...]

DIR is a scripts/consumer-check output (its mitsuba/ and threejs/ folders).
"""

import argparse
import json
import os
import sys

import consumer_scene as cs
import numpy as np

from slicecap.analytic_models import model_of_table
from slicecap.fitted_material import read_fitted_material
from slicecap.png import read_png

SPHERE_RADIUS_M = 0.5
SAMPLES = 4  # per pixel side, for the renders compared with Mitsuba's


def render_exact(brdf, gltf: str, view: dict, samples: int = 1) -> np.ndarray:
    """(size, size, 3) linear radiance of `brdf` (a slicecap.grid.Brdf in the glTF tangent frame)
    on the glTF's sphere under the view's camera and point light: the mean of samples x samples
    rays on a regular grid over each pixel (a box filter, as Mitsuba's film), or its centre."""
    if samples > 1:
        fine = render_exact(brdf, gltf, dict(view, size_px=view["size_px"] * samples))
        size = view["size_px"]
        return fine.reshape(size, samples, size, samples, 3).mean(axis=(1, 3))
    sphere = cs.read_sphere(gltf)
    size = view["size_px"]
    camera, target = np.array(view["camera_position"]), np.array(view["target"])
    forward = (target - camera) / np.linalg.norm(target - camera)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = np.tan(np.radians(view["fov_deg"]) / 2)
    centres = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(centres * half, -centres * half)
    rays = forward + x[..., None] * right + y[..., None] * up
    rays /= np.linalg.norm(rays, axis=-1, keepdims=True)
    oc = camera - sphere.centre
    b = rays @ oc
    disc = b * b - (oc @ oc - SPHERE_RADIUS_M ** 2)
    hit = disc > 0
    t = -b - np.sqrt(np.where(hit, disc, 0.0))
    points = camera + t[..., None] * rays
    normals = (points - sphere.centre) / SPHERE_RADIUS_M
    nearest = np.argmax(normals[hit] @ sphere.normals.T, axis=1)
    tangents = np.zeros_like(normals)
    n = normals[hit]
    tan = sphere.tangents[nearest]
    tan -= n * np.sum(n * tan, -1, keepdims=True)
    tangents[hit] = tan / np.linalg.norm(tan, axis=-1, keepdims=True)
    bitangents = np.cross(normals, tangents)
    to_light = np.array(view["light_position"]) - points
    distance2 = np.sum(to_light * to_light, -1)
    to_light /= np.sqrt(distance2)[..., None]
    to_view = -rays

    def local(w):
        return np.stack([np.sum(w * tangents, -1), np.sum(w * bitangents, -1),
                         np.sum(w * normals, -1)], -1)

    light_local, view_local = local(to_light), local(to_view)
    lit = hit & (light_local[..., 2] > 0) & (view_local[..., 2] > 0)
    image = np.zeros((size, size, 3))
    value = brdf(light_local[lit], view_local[lit])
    image[lit] = (value * (view["light_intensity_w_sr"] * light_local[lit][:, 2:3]
                           / distance2[lit][:, None]))
    return image


def delta_e(reference8: np.ndarray, test8: np.ndarray) -> float:
    return cs.compare_8bit(reference8, test8, cs.lit_mask(reference8) | cs.lit_mask(test8))[
        "delta_e"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--consumer-out", required=True)
    parser.add_argument("materials", nargs="*", help="default: every row of the mitsuba section")
    args = parser.parse_args()
    mitsuba = os.path.join(args.consumer_out, "mitsuba")
    threejs = os.path.join(args.consumer_out, "threejs")
    with open(os.path.join(mitsuba, "mitsuba-results.json"), encoding="utf-8") as file:
        rows = [r for r in json.load(file) if not args.materials or r["material"] in args.materials]
    print("| material | numpy exact vs Mitsuba truth | Mitsuba tabulated fit vs exact fit | "
          "three.js stock vs exact fit | three.js by the specification vs exact fit |")
    print("|---|---|---|---|---|")
    for row in rows:
        name, exposure = row["material"], row["exposure"]
        gltf = os.path.join(mitsuba, f"{name}.gltf")
        view = row["view"]
        truth_brdf = model_of_table(os.path.join(mitsuba, f"{name}.exr")).evaluate
        fit_brdf = read_fitted_material(os.path.join(mitsuba, f"{name}.json")).evaluate
        # Box-filtered as Mitsuba's film for the rows against Mitsuba; pixel centres, as three.js
        # shades them (no antialiasing), for the rows against three.js.
        truth = cs.encode(render_exact(truth_brdf, gltf, view, SAMPLES), exposure)
        exact_box = cs.encode(render_exact(fit_brdf, gltf, view, SAMPLES), exposure)
        exact = cs.encode(render_exact(fit_brdf, gltf, view), exposure)

        mitsuba_truth, mitsuba_tabulated = (
            cs.encode(np.load(os.path.join(mitsuba, f"{name}-mitsuba-{key}.npy")), exposure)
            for key in ("truth", "fit-tabulated"))
        stock = read_png(os.path.join(threejs, f"{name}-threejs.png"))[..., :3]
        spec = read_png(os.path.join(threejs, f"{name}-threejs-spec.png"))[..., :3]
        print(f"| {name} | {delta_e(mitsuba_truth, truth):.2f} | "
              f"{delta_e(exact_box, mitsuba_tabulated):.2f} | {delta_e(exact, stock):.2f} | "
              f"{delta_e(exact, spec):.2f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
