"""The fit's clear coat rendered by the real consumers (scripts/consumer-check, section "coat"): one
coated material, a rough blue dielectric under a glossy clear coat (LACQUER of lacquer.py, which
python/tests/test_material_export.py checks too), written as a fitted material, tabulated by
`slicecap generate TRUTH.json`, fitted (`slicecap fit`, which must choose "ggx+coat") and exported;
then rendered, in the scene of consumer_scene.py, by Mitsuba 3 (the --mitsuba snippet: the coat
blended in, `coat-form`), three.js (the --gltf, KHR_materials_clearcoat) and Blender (Cycles, the
--gltf through Blender's importer, which is also asked what it put on the Principled BSDF's Coat
inputs).

Reference: as for every coated or sheened fit of the other sections (consumer_scene's
mitsuba_reference), the fit tabulated on the 81 x 81 grid and rendered through the slicecap table
plugin. Reported: mean CIE76 dE of 8-bit sRGB over the pixels lit in either image, p95 beside.

For information: the lacquer rendered exactly (CoatedTruth in the slicecap_analytic BSDF), and
every render against it too, since the 81-direction grid smears a coat lobe as narrow as alpha
0.08; the pixels where the coat shows (the truth with and without it >= COAT_REGION_DE apart),
split into its highlight and the rim it dims; and the highlight again at the truth's peak
exposure, where no render clips. The same three consumers also render the fit with coat_weight 0
(the fitted JSON with its coat weight set to 0, exported again by `slicecap fit F.json`, which does
not fit again), judged against the same coated references: how much of the picture the coat is.
Each consumer's coated render must be nearer the reference than its uncoated one (else the
comparison could not see the coat), and within its section's tolerance (three.js 4, Blender 8, the
snippet 3).

Usage: coat_consumers.py --cli build/app/slicecap --out DIR --blender-python VENV/bin/python
       [--three tools/consumers/node_modules/three] [--chromium chromium] [--spp 16]
       (--blender-python none: no Blender)
"""

import argparse
import json
import os
import subprocess
import sys

import consumer_scene as cs
import mitsuba_fit_vs_table as mft
import numpy as np
import threejs_gltf
from lacquer import LACQUER

from slicecap import tabulate, write_abrdf_exr
from slicecap.analytic_models import Term
from slicecap.fitted_material import COAT_F0, parse_fitted_material, read_fitted_material
from slicecap.image_metrics import delta_e_8bit, exposure_of
from slicecap.png import write_png

NAME = "lacquer"
TOLERANCE = {"mitsuba": 3.0, "threejs": 4.0, "blender": 8.0}
# The coat's highlight at the truth's peak exposure against the exact truth: measured 0.54-0.90
# (docs/results/2026-12-02-consumer-renders.md, 2026-12-03 coat section); a coat of the wrong
# roughness is far above it while the means over the sphere hardly move.
HIGHLIGHT_TOLERANCE = 2.0
COAT_REGION_DE = 5.0
COAT_INPUTS = ("Coat Weight", "Coat Roughness", "Coat IOR", "Coat Tint")


class CoatedTruth:
    """LACQUER exactly, in the form slicecap_analytic evaluates (channels(light, view, xp), numpy
    or Dr.Jit): the base (Lambert + GGX with Schlick's f90 1, analytic_models' "ggx" term) dimmed
    by 1 - w Fc and the coat's GGX lobe (the same term with f0 1: no Fresnel) times w Fc, Fc
    Schlick's of IOR 1.5 at the view's cosine: fitted_material's "+coat" model. Rendered in place
    of a table, it shows what the tabulated reference's grid interpolation costs."""

    def __init__(self, parameters: dict) -> None:
        p = {name: entry["value"] for name, entry in parameters.items()}
        if p["specular_f90"] != 1.0:
            raise ValueError("CoatedTruth: analytic_models' GGX term has Schlick's f90 = 1 only")
        self.description = f"lacquer {p}"
        self.weight = p["coat_weight"]
        self.base = Term("ggx", {"diffuse": tuple(p["diffuse_albedo"]), "f0": tuple(
            p["specular_f0"]), "ax": p["alpha_tangent"], "ay": p["alpha_bitangent"],
                                 "tangent_deg": p["tangent_deg"]})
        self.coat = Term("ggx", {"diffuse": (0.0, 0.0, 0.0), "f0": (1.0, 1.0, 1.0),
                                 "ax": p["coat_alpha"], "ay": p["coat_alpha"], "tangent_deg": 0.0})

    def channels(self, light, view, xp):
        one_minus = 1.0 - view[2]
        fresnel = self.weight * (COAT_F0 + (1.0 - COAT_F0) * one_minus * one_minus * one_minus
                                 * one_minus * one_minus)
        base, coat = self.base.channels(light, view, xp), self.coat.channels(light, view, xp)
        return tuple(base[c] * (1.0 - fresnel) + coat[c] * fresnel for c in range(3))


def truth_formula_difference() -> float:
    """Largest relative difference between CoatedTruth (numpy) and slicecap.fitted_material's
    model of LACQUER at 1000 random pairs above the surface (seed 0): the transcription checked."""
    rng = np.random.default_rng(0)

    def directions() -> np.ndarray:
        v = rng.normal(size=(1000, 3))
        v[:, 2] = np.abs(v[:, 2]) + 0.05
        return v / np.linalg.norm(v, axis=1)[:, None]

    light, view = directions(), directions()
    fitted = parse_fitted_material(LACQUER, "LACQUER").evaluate(light, view)
    exact = np.stack(CoatedTruth(LACQUER["parameters"]).channels(tuple(light.T), tuple(view.T),
                                                                 np), axis=-1)
    return float(np.max(np.abs(exact - fitted) / np.abs(fitted)))


def run_cli(*args) -> str:
    return subprocess.run(list(args), check=True, capture_output=True, text=True).stdout


def prepare(cli: str, out: str, clearcoat_roughness: float | None) -> dict:
    """The truth, its table, the fit and its exports, and the fit without its coat: paths."""
    paths = {"truth": os.path.join(out, f"{NAME}-truth.json"),
             "table": os.path.join(out, f"{NAME}.exr")}
    with open(paths["truth"], "w", encoding="utf-8") as file:
        json.dump(LACQUER, file, indent=1)
    run_cli(cli, "generate", paths["truth"], "-o", paths["table"])
    for variant in ("coat", "nocoat"):
        stem = os.path.join(out, NAME if variant == "coat" else f"{NAME}-nocoat")
        paths[variant] = {"json": stem + ".json", "gltf": stem + ".gltf", "xml": stem + ".xml"}
    coat = paths["coat"]
    paths["fit_log"] = run_cli(cli, "fit", paths["table"], "-o", coat["json"], "--gltf",
                               coat["gltf"], "--mitsuba", coat["xml"])
    with open(coat["json"], encoding="utf-8") as file:
        fitted = json.load(file)
    if fitted["model"] != "ggx+coat":
        raise RuntimeError(f"the fit of {paths['truth']} chose {fitted['model']}, not ggx+coat")
    if clearcoat_roughness is not None:  # the negative control: the check must fail
        with open(coat["gltf"], encoding="utf-8") as file:
            gltf = json.load(file)
        gltf["materials"][0]["extensions"]["KHR_materials_clearcoat"][
            "clearcoatRoughnessFactor"] = clearcoat_roughness
        with open(coat["gltf"], "w", encoding="utf-8") as file:
            json.dump(gltf, file)
    fitted["parameters"]["coat_weight"]["value"] = 0.0
    with open(paths["nocoat"]["json"], "w", encoding="utf-8") as file:
        json.dump(fitted, file, indent=1)
    nocoat = paths["nocoat"]
    paths["nocoat_log"] = run_cli(cli, "fit", nocoat["json"], "--gltf", nocoat["gltf"],
                                  "--mitsuba", nocoat["xml"])
    return paths


def mitsuba_renders(paths: dict, out: str, spp: int) -> tuple[dict, dict]:
    """Linear renders: the reference (the coated fit tabulated, through the table plugin), the
    truth's table (information), and each variant's snippet and tabulated fit."""
    mi = mft.use_mitsuba()
    sphere = cs.read_sphere(paths["coat"]["gltf"])
    view = cs.view_of(sphere)
    tangent_deg = read_fitted_material(paths["coat"]["json"]).tangent_deg
    u0 = mft.mesh(sphere, 0.0, os.path.join(out, f"{NAME}-u0.ply"))
    ufit = mft.mesh(sphere, tangent_deg, os.path.join(out, f"{NAME}-ufit.ply"))
    renders = {"table": mft.render(mi, u0, mi.load_dict({"type": "slicecap",
                                                         "filename": paths["table"]}), view, spp)}
    # The truth exactly: slicecap_analytic's BSDF (the table's frame and orientation) with its
    # model replaced by CoatedTruth (the BSDF reads only the model's channels).
    truth = mi.load_dict({"type": "slicecap_analytic", "model": "lambert albedo=0/0/0"})
    truth.model = CoatedTruth(LACQUER["parameters"])
    renders["coat-truth"] = mft.render(mi, u0, truth, view, spp)
    uncoated = dict(LACQUER["parameters"], coat_weight={"value": 0.0})
    truth.model = CoatedTruth(uncoated)
    renders["nocoat-truth"] = mft.render(mi, u0, truth, view, spp)
    for variant in ("coat", "nocoat"):
        files = paths[variant]
        tabulated = files["json"].replace(".json", "-fit-tabulated.exr")
        write_abrdf_exr(tabulated, tabulate(read_fitted_material(files["json"]).evaluate))
        renders[f"{variant}-tabulated"] = mft.render(
            mi, u0, mi.load_dict({"type": "slicecap", "filename": tabulated}), view, spp)
        renders[f"{variant}-mitsuba"] = mft.render(mi, ufit, mft.snippet_bsdf(mi, files["xml"]),
                                                   view, spp)
    return renders, {"view": view.__dict__, "tangent_deg": tangent_deg,
                     "sphere_node": sphere.node_index}


def threejs_renders(paths: dict, out: str, view: dict, three: str, chromium: str) -> dict:
    files: dict = {}
    server = threejs_gltf.serve(os.path.abspath(three), files)
    images = {}
    try:
        for variant in ("coat", "nocoat"):
            key = f"{NAME}-{variant}"
            view_path = os.path.abspath(os.path.join(out, f"{key}-view.json"))
            with open(view_path, "w", encoding="utf-8") as file:
                json.dump(view, file)
            files[f"/m/{key}/model.gltf"] = os.path.abspath(paths[variant]["gltf"])
            files[f"/m/{key}/view.json"] = view_path
            url = f"http://127.0.0.1:{server.server_address[1]}/page.html?m={key}"
            image, material = threejs_gltf.render(chromium, os.path.abspath(
                os.path.join(out, "chromium-profile")), url, view["size_px"])
            images[variant] = (image, material)
    finally:
        server.shutdown()
    return images


def blender_renders(paths: dict, out: str, view: dict, blender_python: str, samples: int) -> dict:
    view_path = os.path.join(out, f"{NAME}-blender-view.json")
    with open(view_path, "w", encoding="utf-8") as file:
        json.dump(view, file)
    results = {}
    for variant in ("coat", "nocoat"):
        prefix = os.path.join(out, f"{NAME}-{variant}-blender")
        subprocess.run([blender_python, threejs_gltf.__file__.replace(
            "threejs_gltf.py", "blender_render.py"), paths[variant]["gltf"], view_path, prefix,
            str(samples)], check=True, capture_output=True)
        with open(prefix + ".json", encoding="utf-8") as file:
            info = json.load(file)
        results[variant] = (np.load(prefix + ".npy"), info)
    return results


def run(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", required=True, help="the slicecap command (generate, fit)")
    parser.add_argument("--out", required=True)
    parser.add_argument("--blender-python", required=True, help="bpy's python, or none")
    parser.add_argument("--three", default="tools/consumers/node_modules/three")
    parser.add_argument("--chromium", default="chromium")
    parser.add_argument("--spp", type=int, default=16, help="Mitsuba and Cycles samples")
    parser.add_argument("--clearcoat-roughness", type=float, help="a negative control: write "
                        "this clearcoatRoughnessFactor into the exported glTF (e.g. the coat's "
                        "alpha instead of its square root); three.js and Blender must then fail")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    difference = truth_formula_difference()
    if difference > 1e-9:
        raise RuntimeError(f"CoatedTruth is not fitted_material's +coat model: {difference:.3g}")
    paths = prepare(args.cli, args.out, args.clearcoat_roughness)
    renders, scene = mitsuba_renders(paths, args.out, args.spp)
    # One exposure, as the mitsuba section: the truth table's render's 99.5th percentile.
    exposure = exposure_of(renders["table"], renders["table"].max(axis=-1) > 0.0)
    eight = {key: cs.encode(image, exposure) for key, image in renders.items()}
    view = dict(scene["view"], exposure=exposure, sphere_node=scene["sphere_node"])
    for variant, (image, material) in threejs_renders(paths, args.out, view, args.three,
                                                      args.chromium).items():
        eight[f"{variant}-threejs"] = image
        scene[f"threejs_{variant}_material"] = material
    if args.blender_python != "none":
        for variant, (image, info) in blender_renders(paths, args.out, scene["view"],
                                                      args.blender_python, args.spp).items():
            eight[f"{variant}-blender"] = cs.encode(image, exposure)
            renders[f"{variant}-blender"] = image
            scene[f"blender_{variant}_principled"] = info["principled"]
            scene["blender"] = info["blender"]
    for key, image in eight.items():
        write_png(os.path.join(args.out, f"{NAME}-{key}.png"), image)

    # The coat's region: the pixels where the exact truth with its coat and without it differ by
    # at least COAT_REGION_DE (its highlight and, toward the rim, its dimming of the base).
    # Its two parts: where the coat brightens the picture (its highlight) and where it darkens it
    # (the base dimmed by 1 - w Fc, toward the rim).
    coat_region = delta_e_8bit(eight["coat-truth"], eight["nocoat-truth"]) >= COAT_REGION_DE
    brighter = (eight["coat-truth"].astype(np.int32).sum(axis=-1)
                > eight["nocoat-truth"].astype(np.int32).sum(axis=-1))
    parts = {"coat_region": coat_region, "coat_highlight": coat_region & brighter,
             "coat_dimmed": coat_region & ~brighter}
    scene.update({f"{part}_pixels": int(mask.sum()) for part, mask in parts.items()})
    # Where the dimmed part lies: its share within 2 px of the edge of what the truth lights.
    def inside(pixels: int) -> np.ndarray:
        lit = cs.lit_mask(eight["nocoat-truth"])
        inner = lit.copy()
        for dy in range(-pixels, pixels + 1):
            for dx in range(-pixels, pixels + 1):
                inner &= np.roll(np.roll(lit, dy, 0), dx, 1)
        return inner

    scene["coat_dimmed_share_within_2px_of_edge"] = float(
        np.mean(~inside(2)[parts["coat_dimmed"]]))

    def against(reference: str, key: str) -> dict:
        pair = cs.compare_8bit(eight[reference], eight[key], cs.lit_mask(eight[reference])
                               | cs.lit_mask(eight[key]))
        for part, mask in parts.items():
            pair[part] = cs.compare_8bit(eight[reference], eight[key], mask)
        return pair

    scene["truth_formula_max_relative_difference"] = difference
    print(f"coat: the exact truth's formula against fitted_material's: largest relative "
          f"difference {difference:.1e} at 1000 random pairs")
    print(f"coat: {paths['fit_log'].splitlines()[0]}; the coat's region (truth with and "
          f"without the coat >= {COAT_REGION_DE:g} dE apart): {scene['coat_region_pixels']} px, "
          f"{scene['coat_highlight_pixels']} brighter with it, {scene['coat_dimmed_pixels']} "
          f"darker ({100 * scene['coat_dimmed_share_within_2px_of_edge']:.0f} % of these within "
          f"2 px of the lit edge)")
    # The coat's highlight unclipped: at the exposure above its core is 255 in every coated render
    # (the exposure is the table's 99.5th percentile); at the truth's peak (its brightest channel)
    # nothing is clipped. three.js renders again at that exposure (its page divides by it).
    peak = float(renders["coat-truth"].max())
    peak8 = {consumer: cs.encode(renders[f"coat-{consumer}"], peak)
             for consumer in ("truth", "tabulated", "mitsuba", "blender")
             if f"coat-{consumer}" in renders}
    peak_out = os.path.join(args.out, "peak-exposure")
    os.makedirs(peak_out, exist_ok=True)
    peak8["threejs"] = threejs_renders(paths, peak_out, dict(view, exposure=peak), args.three,
                                       args.chromium)["coat"][0]
    for consumer, image in peak8.items():
        write_png(os.path.join(peak_out, f"{NAME}-coat-{consumer}.png"), image)

    def linear_sum(image8: np.ndarray, mask: np.ndarray) -> float:
        x = image8[mask] / 255.0
        linear = np.where(x <= 0.04045, x / 12.92, ((x + 0.055) / 1.055) ** 2.4)
        return float(np.sum(linear @ np.array([0.2126, 0.7152, 0.0722])))

    highlight = parts["coat_highlight"]
    scene["peak_exposure"] = {"exposure": peak, "rows": {}}
    for consumer, image in peak8.items():
        pair = cs.compare_8bit(peak8["truth"], image, highlight)
        pair["luminance_over_truth"] = (linear_sum(image, highlight)
                                        / linear_sum(peak8["truth"], highlight))
        pair["saturated_pixels"] = int((image >= 255).any(axis=-1).sum())
        scene["peak_exposure"]["rows"][consumer] = pair
        print(f"coat {consumer:9s} at the truth's peak exposure, the coat's highlight "
              f"({pair['lit_pixels']} px) against the exact truth: mean dE {pair['delta_e']:.2f} "
              f"(p95 {pair['delta_e_p95']:.2f}), summed luminance x "
              f"{pair['luminance_over_truth']:.3f} of the truth's, {pair['saturated_pixels']} "
              f"px at 255", flush=True)

    highlight_at_peak = scene["peak_exposure"]["rows"]

    def luminance(key: str) -> np.ndarray:
        """Linear luminance of an 8-bit sRGB render (the exposure's units)."""
        x = eight[key] / 255.0
        linear = np.where(x <= 0.04045, x / 12.92, ((x + 0.055) / 1.055) ** 2.4)
        return linear @ np.array([0.2126, 0.7152, 0.0722])

    # The dimming away from the outline, where the pixels' sampling matters less: at least 3 px
    # inside the lit area, where the truth's coat dims its base by 5 % or more.
    truth_ratio = luminance("coat-truth") / np.maximum(luminance("nocoat-truth"), 1e-12)
    parts["dimmed_inside"] = inside(3) & (truth_ratio > 0.0) & (truth_ratio <= 0.95)
    scene["dimmed_inside_pixels"] = int(parts["dimmed_inside"].sum())

    def coat_ratio(consumer: str, part: str) -> float:
        """Median of the consumer's own coated / uncoated luminance over a part of the coat's
        region (pixels lit in both): how much its coat brightens or dims, apart from its base."""
        coated, bare = luminance(f"coat-{consumer}"), luminance(f"nocoat-{consumer}")
        mask = parts[part] & (coated > 0.0) & (bare > 0.0)
        return float(np.median(coated[mask] / bare[mask]))

    rows, failed = [], []
    for consumer in ("mitsuba", "threejs", "blender", "tabulated", "truth"):
        if f"coat-{consumer}" not in eight:
            print(f"coat {consumer:9s}: not rendered")
            continue
        row = {"consumer": consumer, "coat": against("coat-tabulated", f"coat-{consumer}"),
               "nocoat": against("coat-tabulated", f"nocoat-{consumer}"),
               "coat_vs_truth": against("coat-truth", f"coat-{consumer}"),
               "nocoat_vs_truth": against("coat-truth", f"nocoat-{consumer}")}
        row["coat_over_nocoat"] = {part: coat_ratio(consumer, part)
                                   for part in ("coat_highlight", "coat_dimmed",
                                                "dimmed_inside")}
        if consumer == "tabulated":  # the reference itself: against the truth only
            row["coat"] = None
        elif consumer == "truth":  # the truth itself: against the reference only
            row["coat_vs_truth"] = None
        else:
            row["ok"] = (row["coat"]["delta_e"] <= TOLERANCE[consumer]
                         and row["coat"]["delta_e"] < row["nocoat"]["delta_e"]
                         and highlight_at_peak[consumer]["delta_e"] <= HIGHLIGHT_TOLERANCE)
            if not row["ok"]:
                failed.append(consumer)
        rows.append(row)

        def text(pair):
            return ("(itself)" if pair is None else
                    f"{pair['delta_e']:.2f} (p95 {pair['delta_e_p95']:.2f}; coat's region "
                    f"{pair['coat_region']['delta_e']:.2f}: highlight "
                    f"{pair['coat_highlight']['delta_e']:.2f}, dimmed "
                    f"{pair['coat_dimmed']['delta_e']:.2f})")

        print(f"coat {consumer:9s} mean dE vs the tabulated coated fit: {text(row['coat'])}, "
              f"without the coat {text(row['nocoat'])}; vs the exact truth: "
              f"{text(row['coat_vs_truth'])}, without the coat {text(row['nocoat_vs_truth'])}; "
              f"its coated / uncoated luminance, median: highlight "
              f"{row['coat_over_nocoat']['coat_highlight']:.3f}, dimmed "
              f"{row['coat_over_nocoat']['coat_dimmed']:.3f}, dimmed >= 3 px inside "
              f"({scene['dimmed_inside_pixels']} px) "
              f"{row['coat_over_nocoat']['dimmed_inside']:.3f}"
              f"{'  FAIL' if consumer in failed else ''}", flush=True)
    for variant in ("coat", "nocoat"):
        if f"blender_{variant}_principled" in scene:
            principled = scene[f"blender_{variant}_principled"]
            print(f"coat blender {scene['blender']} imported {variant}: " + ", ".join(
                f"{name} {principled.get(name)}" for name in COAT_INPUTS))
        if f"threejs_{variant}_material" in scene:
            print(f"coat threejs loaded {variant}: {scene[f'threejs_{variant}_material']}")
    with open(os.path.join(args.out, "coat-results.json"), "w", encoding="utf-8") as file:
        json.dump({"exposure": exposure, "scene": scene, "rows": rows,
                   "fit_log": paths["fit_log"], "nocoat_log": paths["nocoat_log"]}, file,
                  indent=1)
    print(f"coat: {'FAIL: ' + ', '.join(failed) if failed else 'ok'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
