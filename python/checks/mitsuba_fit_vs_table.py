"""Mitsuba 3 renders of the fit against the measured table (scripts/consumer-check, section
"mitsuba"): for every built-in anisotropic material, `slicecap generate` makes the true table,
`slicecap fit` fits it and writes the glTF and the Mitsuba snippet; Mitsuba renders, in the scene of
consumer_scene.py (the glTF's sphere, one point light, one camera), the table through the slicecap
BSDF plugin and the snippet's own BSDF. Reported: mean CIE76 dE of 8-bit sRGB over the lit pixels
(lit in either render), goal <= --goal. A negative control renders the snippet with its tangent
turned by 90 deg: it must be farther from the table than the goal, or the check could not see a
wrong frame.

The snippet's BSDF has no rotation (docs/material-export.md, "Mitsuba 3"): its alpha_u follows the
shape's dp/du, so the sphere is given UVs whose u runs along the glTF tangent turned by the fit's
tangent_deg (consumer_scene.unshared_mesh_with_tangent_uvs); the table is rendered with u along the
glTF tangent itself, the table's x axis. Each render is also saved (linear .npy, 8-bit PNG) for
the three.js and Blender sections, which compare with Mitsuba's render of the fit.

Information beside the goal (which stays against the measured table): the analytic model behind
each table (slicecap.analytic_models, read from the table's slicecap:model) rendered exactly by
the BSDF `slicecap_analytic` in the table's frame, and both the snippet and the table against it:
the table's row says what the 81-direction grid's linear interpolation costs, the snippet's what
the fit and its export cost against the material itself.

A fit with a clear coat (model "ggx+coat" or "ggx+sheen+coat") goes through unchanged: the
tabulated fit is slicecap.fitted_material's model, coat included, and the snippet is what
`slicecap fit --mitsuba` writes for it.

Usage: mitsuba_fit_vs_table.py --cli build/app/slicecap --out DIR [--spp 16] [--goal 3]
"""

import argparse
import json
import os
import re
import subprocess
import sys

import consumer_scene as cs
import numpy as np

from slicecap import tabulate, write_abrdf_exr
from slicecap.fitted_material import read_fitted_material
from slicecap.image_metrics import exposure_of
from slicecap.png import write_png

VARIANT = "llvm_ad_rgb"


def use_mitsuba():
    import mitsuba as mi

    mi.set_variant(VARIANT)
    import slicecap.mitsuba_bsdf

    slicecap.mitsuba_bsdf.register()
    return mi


def anisotropic_materials(cli: str) -> list[str]:
    """The CLI's built-in anisotropic materials: those of `slicecap generate --list` with a lobe
    whose two alphas differ (`ax=A ay=B`, A != B)."""
    listing = subprocess.run([cli, "generate", "--list"], check=True, capture_output=True,
                             text=True).stdout
    names = []
    for line in listing.splitlines():
        pairs = re.findall(r"ax=([0-9.eE+-]+) ay=([0-9.eE+-]+)", line)
        if any(float(ax) != float(ay) for ax, ay in pairs):
            names.append(line.split()[0])
    if not names:
        raise RuntimeError(f"`{cli} generate --list` listed no anisotropic material:\n{listing}")
    return names


def scene(mi, mesh_path: str, bsdf, view: cs.View, spp: int):
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "sensor": {
            "type": "perspective",
            "fov": view.fov_deg,
            "to_world": mi.ScalarTransform4f().look_at(
                origin=view.camera_position, target=view.target, up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": view.size_px, "height": view.size_px,
                     "pixel_format": "rgb", "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "sphere": {"type": "ply", "filename": mesh_path, "bsdf": bsdf},
        "light": {"type": "point", "position": view.light_position,
                  "intensity": {"type": "rgb", "value": view.light_intensity_w_sr}},
    })


def render(mi, mesh_path, bsdf, view, spp) -> np.ndarray:
    return np.array(mi.render(scene(mi, mesh_path, bsdf, view, spp), seed=0), dtype=np.float64)


def mesh(sphere: cs.Sphere, angle_deg: float, path: str) -> str:
    cs.write_ply(path, *cs.unshared_mesh_with_tangent_uvs(sphere, angle_deg))
    return path


def snippet_bsdf(mi, xml_path: str):
    """The BSDF of the exported snippet (its sample shape's), as Mitsuba loaded it."""
    for shape in mi.load_file(xml_path).shapes():
        if shape.id() == "slicecap_sample":
            return shape.bsdf()
    raise RuntimeError(f"{xml_path}: no shape slicecap_sample")


def one_material(mi, cli, name, out, spp, goal) -> dict:
    table = os.path.join(out, f"{name}.exr")
    fit = os.path.join(out, f"{name}.json")
    gltf = os.path.join(out, f"{name}.gltf")
    xml = os.path.join(out, f"{name}.xml")
    subprocess.run([cli, "generate", name, "-o", table], check=True, capture_output=True)
    subprocess.run([cli, "fit", table, "-o", fit, "--gltf", gltf, "--mitsuba", xml], check=True,
                   capture_output=True)
    with open(fit, encoding="utf-8") as file:
        tangent_deg = json.load(file)["parameters"]["tangent_deg"]["value"]
    sphere = cs.read_sphere(gltf)
    view = cs.view_of(sphere)
    bsdf = snippet_bsdf(mi, xml)
    renders = {
        "table": render(mi, mesh(sphere, 0.0, os.path.join(out, f"{name}-u0.ply")),
                        mi.load_dict({"type": "slicecap", "filename": table}), view, spp),
        "fit": render(mi, mesh(sphere, tangent_deg, os.path.join(out, f"{name}-ufit.ply")),
                      bsdf, view, spp),
        "control": render(mi, mesh(sphere, tangent_deg + 90.0,
                                   os.path.join(out, f"{name}-ufit90.ply")), bsdf, view, spp),
    }
    # Information, to tell the fit's error from the table's interpolation: the fitted material
    # tabulated on the same 81 x 81 grid and rendered through the same plugin.
    fit_table = os.path.join(out, f"{name}-fit-tabulated.exr")
    write_abrdf_exr(fit_table, tabulate(read_fitted_material(fit).evaluate))
    renders["fit-tabulated"] = render(mi, os.path.join(out, f"{name}-u0.ply"),
                                      mi.load_dict({"type": "slicecap", "filename": fit_table}),
                                      view, spp)
    # Information, to tell the grid's interpolation from the fit's error: the analytic model
    # behind the table (its slicecap:model, the C++ description), rendered exactly by the BSDF
    # slicecap_analytic in the table's frame (u along the glTF tangent, as the table's render).
    renders["truth"] = render(mi, os.path.join(out, f"{name}-u0.ply"),
                              mi.load_dict({"type": "slicecap_analytic", "filename": table}),
                              view, spp)
    # One exposure for all of a material's renders: the table's 99.5th percentile on the sphere.
    exposure = exposure_of(renders["table"], renders["table"].max(axis=-1) > 0.0)
    eight = {k: cs.encode(v, exposure) for k, v in renders.items()}
    for key, image in renders.items():
        np.save(os.path.join(out, f"{name}-mitsuba-{key}.npy"), image)
        write_png(os.path.join(out, f"{name}-mitsuba-{key}.png"), eight[key])
    lit = cs.lit_mask(eight["table"]) | cs.lit_mask(eight["fit"])
    row = {"material": name, "tangent_deg": tangent_deg, "exposure": exposure,
           "view": view.__dict__, **cs.compare_8bit(eight["table"], eight["fit"], lit)}
    control_lit = cs.lit_mask(eight["table"]) | cs.lit_mask(eight["control"])
    row["control_delta_e"] = cs.compare_8bit(eight["table"], eight["control"],
                                             control_lit)["delta_e"]
    for key, reference, test in (("tabulated_fit_vs_table", "table", "fit-tabulated"),
                                 ("fit_vs_tabulated_fit", "fit-tabulated", "fit"),
                                 ("fit_vs_truth", "truth", "fit"),
                                 ("table_vs_truth", "truth", "table")):
        pair_lit = cs.lit_mask(eight[reference]) | cs.lit_mask(eight[test])
        pair = cs.compare_8bit(eight[reference], eight[test], pair_lit)
        row[key] = pair["delta_e"]
        row[key + "_p95"] = pair["delta_e_p95"]
    row["ok"] = row["delta_e"] <= goal and row["control_delta_e"] > goal
    return row


def run(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", required=True, help="the slicecap command (generate, fit)")
    parser.add_argument("--out", required=True, help="folder for tables, exports and renders")
    parser.add_argument("--spp", type=int, default=16, help="samples per pixel (default 16)")
    parser.add_argument("--goal", type=float, default=3.0, help="max mean dE (default 3)")
    parser.add_argument("--materials", nargs="*", help="default: every built-in anisotropic one")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    mi = use_mitsuba()
    rows = []
    for name in args.materials or anisotropic_materials(args.cli):
        row = one_material(mi, args.cli, name, args.out, args.spp, args.goal)
        rows.append(row)
        print(f"mitsuba {name:18s} fit vs table: mean dE {row['delta_e']:.2f} (p95 "
              f"{row['delta_e_p95']:.2f}, {row['lit_pixels']} lit px); control (tangent + 90 deg) "
              f"{row['control_delta_e']:.2f}{'' if row['ok'] else '  FAIL'}; information: "
              f"tabulated fit vs table {row['tabulated_fit_vs_table']:.2f}, fit vs tabulated fit "
              f"{row['fit_vs_tabulated_fit']:.2f}; against the analytic truth: fit "
              f"{row['fit_vs_truth']:.2f} (p95 {row['fit_vs_truth_p95']:.2f}), table "
              f"{row['table_vs_truth']:.2f} (p95 {row['table_vs_truth_p95']:.2f})", flush=True)
    with open(os.path.join(args.out, "mitsuba-results.json"), "w", encoding="utf-8") as file:
        json.dump(rows, file, indent=1)
    failed = [r["material"] for r in rows if not r["ok"]]
    print(f"mitsuba: worst mean dE {max(r['delta_e'] for r in rows):.2f} (goal {args.goal:g}); "
          f"{'FAIL: ' + ', '.join(failed) if failed else 'ok'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
