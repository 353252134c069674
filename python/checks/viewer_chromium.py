"""The material viewer in a real browser (scripts/consumer-check, section "viewer"): headless
Chromium renders the page (python -m slicecap.viewer) at fixed light and camera positions (the
page's URL hash), and the sphere panels of its screenshot are compared with the numpy renderer's
picture of the same table and fitted material under the same light
(slicecap.render.render_sphere_point_light): mean CIE76 dE and relative RMSE of the 8-bit sRGB
values over the sphere (its silhouette eroded by 2 pixels, where rasterised triangles and the
ray-cast sphere differ by design). Exit 0 when every mean dE is within --tolerance, 1 otherwise.

Materials: built-in ones, tabulated (`slicecap generate`) and fitted (`slicecap fit`) by the CLI,
and a clear-coated one (COATED, model ggx+sheen+coat) whose fit JSON is written here and whose
table is that material tabulated by slicecap.fitted_material: the page's coat, sheen and lobe
against the numpy model, whatever model `slicecap fit` chooses for the built-ins. Its screenshot
must also differ from the same material without its coat by more than the tolerance, or the check
could not see a missing coat.

Usage: viewer_chromium.py --cli build/app/slicecap --out DIR [--chromium chromium]
"""

import argparse
import dataclasses
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

from slicecap import viewer_scene
from slicecap.abrdf_exr import write_abrdf_exr
from slicecap.fitted_material import FittedMaterial, has_coat, read_fitted_material
from slicecap.grid import tabulate
from slicecap.image_metrics import delta_e_8bit, to_8bit
from slicecap.materials import load_material
from slicecap.png import read_png
from slicecap.render import render_sphere_point_light
from slicecap.viewer import build_page, table_brdf

MATERIALS = ("brushed-steel-30", "satin-blue-45", "velvet-red")
# A dim blue brushed lobe with a sheen under a strong coat: a shader that dropped the coat from
# the point light's term alone (the environment's albedo, computed in Python, keeping it) moves
# the fit panel by mean dE ~1.2 and ~0.8 at the two views (numpy), above the tolerance at both.
COATED = ("coated-blue-satin", FittedMaterial(
    "ggx+sheen+coat", (0.02, 0.03, 0.12), (0.1, 0.12, 0.2), 1.0, 0.4, 0.1, 30.0,
    sheen_colour=(0.3, 0.3, 0.6), sheen_roughness=0.4, coat_weight=0.9, coat_alpha=0.15))
# (light azimuth, light elevation, camera yaw, camera pitch) in degrees.
VIEWS = ((35.0, 35.0, 0.0, 15.0), (-70.0, 20.0, 30.0, 35.0))
PANEL_SIZE = 256
ENV = 0.15
# Swiftshader needs --enable-unsafe-swiftshader since Chromium 137: without it WebGL falls back
# to nothing headless (measured with Debian's chromium 156).
CHROMIUM_FLAGS = [
    "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    "--hide-scrollbars", "--force-device-scale-factor=1", "--disable-gpu-sandbox",
    f"--window-size={2 * PANEL_SIZE + 400},{2 * PANEL_SIZE}",
]


def chromium(binary: str, profile: str, *arguments) -> subprocess.CompletedProcess:
    return subprocess.run(
        [binary, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", *arguments],
        capture_output=True, text=True, timeout=180,
    )


def page_state(binary: str, profile: str, url: str) -> str:
    """'' when the page rendered (its body says data-rendered="yes"), else what it said."""
    dom = chromium(binary, profile, "--dump-dom", url).stdout
    if 'data-rendered="yes"' in dom:
        return ""
    error = re.search(r'<pre id="error"[^>]*>(.*?)</pre>', dom, re.S)
    return error.group(1).strip() if error and error.group(1).strip() else "the page did not render"


def compare(screenshot8: np.ndarray, reference8: np.ndarray, mask: np.ndarray) -> dict:
    a = screenshot8[mask].astype(np.float64)
    b = reference8[mask].astype(np.float64)
    return {
        "delta_e": float(np.mean(delta_e_8bit(reference8[mask], screenshot8[mask]))),
        "delta_e_p99": float(np.percentile(delta_e_8bit(reference8[mask], screenshot8[mask]), 99)),
        "relative_rmse": float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b**2))),
        "max_abs_8bit": int(np.max(np.abs(a - b))),
    }


def erode(mask: np.ndarray, pixels: int) -> np.ndarray:
    for _ in range(pixels):
        inner = mask.copy()
        inner[1:] &= mask[:-1]
        inner[:-1] &= mask[1:]
        inner[:, 1:] &= mask[:, :-1]
        inner[:, :-1] &= mask[:, 1:]
        mask = inner
    return mask


def control_row(results, name, fit, albedo, crop, exposure, mask, tolerance) -> bool:
    """The negative control: the same screenshot against the fit with its tangent turned by
    90 deg. For a fit with an anisotropic specular lobe (f0 or f90 above 0.01, its two alphas
    unequal) its dE must be above the tolerance, or the check could not see a wrong frame; False
    then. A fit without one has no tangent to turn and passes: a pure sheen, or an isotropic lobe
    (velvet-red's khr_materials_sheen fit: f0 0.14 at alphas 1 and 1), which turns into itself."""
    turned = dataclasses.replace(fit, tangent_deg=fit.tangent_deg + 90.0)
    light_az, light_el, yaw, pitch = VIEWS[0]
    image, _ = render_sphere_point_light(
        turned.evaluate, albedo, PANEL_SIZE, light_az, light_el, yaw, pitch, ENV)
    metrics = compare(crop, to_8bit(image, 1.0 / exposure), erode(mask, 2))
    results.append({"material": name, "panel": "control: fit, tangent + 90 deg", **metrics})
    has_lobe = max(max(fit.specular_f0), fit.specular_f90) > 0.01
    anisotropic = fit.alpha_tangent != fit.alpha_bitangent
    seen = metrics["delta_e"] > tolerance or not (has_lobe and anisotropic)
    print(f"viewer {name:17s} control (tangent + 90 deg, must differ): mean dE "
          f"{metrics['delta_e']:.3f}, rel. RMSE {metrics['relative_rmse']:.4f}"
          f"{'' if has_lobe else ' (no specular lobe: no tangent to see)'}"
          f"{'' if anisotropic or not has_lobe else ' (isotropic lobe: no tangent to see)'}"
          f"{'' if seen else '  NOT SEEN: the check is blind'}")
    return seen


def coat_control_row(results, name, fit, crop, exposure, mask, tolerance) -> bool:
    """The coat's negative control: the same screenshot against the fit without its coat must be
    farther than the tolerance, or the check could not see a page that dropped the coat."""
    bare = dataclasses.replace(fit, model=fit.model.removesuffix("+coat"))
    light_az, light_el, yaw, pitch = VIEWS[0]
    image, _ = render_sphere_point_light(
        bare.evaluate, viewer_scene.directional_albedo(bare.evaluate), PANEL_SIZE, light_az,
        light_el, yaw, pitch, ENV)
    metrics = compare(crop, to_8bit(image, 1.0 / exposure), erode(mask, 2))
    results.append({"material": name, "panel": "control: fit without its coat", **metrics})
    seen = metrics["delta_e"] > tolerance
    print(f"viewer {name:17s} control (coat removed, must differ): mean dE "
          f"{metrics['delta_e']:.3f}, rel. RMSE {metrics['relative_rmse']:.4f}"
          f"{'' if seen else '  NOT SEEN: the check is blind'}")
    return seen


def fit_document(material: FittedMaterial) -> dict:
    """A completed `slicecap fit` JSON of `material` (the fields slicecap.viewer reads; no sigmas,
    the metrics of a material that is its own table)."""
    parameters = {}
    for name in FittedMaterial.__dataclass_fields__:
        value = getattr(material, name)
        if name not in ("model", "sheen_form"):
            parameters[name] = {"value": list(value) if isinstance(value, tuple) else value,
                                "sigma": None, "unit": "-"}
    # Format version 2 with the material's own sheen form, so that the fit is its table (COATED's
    # khr_materials_sheen sheen, under the coat, in the browser as the built-in fits' are).
    return {"format": "slicecap-material", "format_version": 2,
            "sheen_form": material.sheen_form, "source": "numpy", "model": material.model,
            "parameters": parameters, "metrics": {"delta_e": 0.0}}


def material_files(cli: str, name: str, out: str) -> tuple[str, str]:
    """(table, fit) paths: a built-in's from the CLI, COATED's written here."""
    table_path = os.path.join(out, f"{name}.exr")
    fit_path = os.path.join(out, f"{name}.json")
    if name == COATED[0]:
        write_abrdf_exr(table_path, tabulate(COATED[1].evaluate))
        with open(fit_path, "w", encoding="utf-8") as file:
            json.dump(fit_document(COATED[1]), file, indent=1)
        return table_path, fit_path
    subprocess.run([cli, "generate", name, "-o", table_path], check=True, capture_output=True)
    subprocess.run([cli, "fit", table_path, "-o", fit_path], check=True, capture_output=True)
    return table_path, fit_path


def run(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", required=True, help="the slicecap command (generate, fit)")
    parser.add_argument("--out", required=True, help="folder for tables, pages, screenshots")
    parser.add_argument("--chromium", default="chromium")
    parser.add_argument("--tolerance", type=float, default=0.5, help="max mean dE (default 0.5)")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    profile = os.path.join(os.path.abspath(args.out), "chromium-profile")
    results, failed = [], False
    for name in (*MATERIALS, COATED[0]):
        table_path, fit_path = material_files(args.cli, name, args.out)
        page = build_page(table_path, fit_path, PANEL_SIZE)
        page_path = os.path.abspath(os.path.join(args.out, f"{name}.html"))
        with open(page_path, "w", encoding="utf-8") as file:
            file.write(page)
        data = json.loads(
            re.search(r'<script id="slicecap-data"[^>]*>(.*?)</script>', page, re.S).group(1)
        )
        exposure = data["exposure"]
        table = load_material(table_path).values
        fit = read_fitted_material(fit_path)
        albedo = {
            "table": viewer_scene.directional_albedo(table_brdf(table)),
            "fit": viewer_scene.directional_albedo(fit.evaluate),
        }
        brdfs = {"table": table_brdf(table), "fit": fit.evaluate}
        for light_az, light_el, yaw, pitch in VIEWS:
            url = (f"file://{page_path}#light={light_az:g},{light_el:g}&camera={yaw:g},{pitch:g}"
                   f"&env={ENV:g}&exposure={exposure!r}")
            problem = page_state(args.chromium, profile, url)
            if problem:
                print(f"viewer: {name}: Chromium did not render the page: {problem}",
                      file=sys.stderr)
                return 1
            shot_path = os.path.join(args.out, f"{name}-{light_az:g}-{light_el:g}.png")
            started = time.perf_counter()
            run_ = chromium(args.chromium, profile, f"--screenshot={shot_path}", url)
            if run_.returncode != 0 or not os.path.exists(shot_path):
                print(f"viewer: {name}: chromium --screenshot failed: {run_.stderr[-500:]}",
                      file=sys.stderr)
                return 1
            seconds = time.perf_counter() - started
            shot = read_png(shot_path)
            # Information, not a check: how far the page's fit panel is from its table panel
            # (the fit's error plus the table's interpolation between grid directions).
            _, sphere = render_sphere_point_light(
                fit.evaluate, albedo["fit"], PANEL_SIZE, light_az, light_el, yaw, pitch, ENV)
            inner = erode(sphere, 2)
            between = compare(shot[:PANEL_SIZE, :PANEL_SIZE],
                              shot[:PANEL_SIZE, PANEL_SIZE:2 * PANEL_SIZE], inner)
            results.append({"material": name, "panel": "information: fit panel vs table panel",
                            "light": [light_az, light_el], "camera": [yaw, pitch], **between})
            print(f"viewer {name:17s} (information) fit panel vs table panel, light "
                  f"{light_az:g},{light_el:g}: mean dE {between['delta_e']:.2f}")
            for panel, column in (("fit", 0), ("table", 1)):
                image, mask = render_sphere_point_light(
                    brdfs[panel], albedo[panel], PANEL_SIZE, light_az, light_el, yaw, pitch, ENV)
                reference8 = to_8bit(image, 1.0 / exposure)
                crop = shot[:PANEL_SIZE, column * PANEL_SIZE:(column + 1) * PANEL_SIZE]
                metrics = compare(crop, reference8, erode(mask, 2))
                row = {"material": name, "panel": panel, "light": [light_az, light_el],
                       "camera": [yaw, pitch], "screenshot_s": round(seconds, 1), **metrics}
                results.append(row)
                ok = metrics["delta_e"] <= args.tolerance
                failed |= not ok
                if panel == "fit" and (light_az, light_el) == VIEWS[0][:2]:
                    failed |= not control_row(results, name, fit, albedo["fit"], crop, exposure,
                                              mask, args.tolerance)
                    if has_coat(fit.model):
                        failed |= not coat_control_row(results, name, fit, crop, exposure, mask,
                                                       args.tolerance)
                print(f"viewer {name:17s} {panel:5s} light {light_az:5g},{light_el:3g} "
                      f"camera {yaw:3g},{pitch:3g}: mean dE {metrics['delta_e']:.3f} "
                      f"(p99 {metrics['delta_e_p99']:.2f}), rel. RMSE "
                      f"{metrics['relative_rmse']:.4f}, max |diff| {metrics['max_abs_8bit']}"
                      f"{'' if ok else '  ABOVE TOLERANCE'}")
    with open(os.path.join(args.out, "viewer-results.json"), "w", encoding="utf-8") as file:
        json.dump(results, file, indent=1)
    worst = max(r["delta_e"] for r in results if r["panel"] in ("fit", "table"))
    print(f"viewer: worst mean dE {worst:.3f} (tolerance {args.tolerance:g}): "
          f"{'FAIL' if failed else 'ok'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
