"""Blender renders the exported glTF (scripts/consumer-check, section "blender"): for each material
of the mitsuba section, PyPI `bpy` (run by --blender-python, a venv of its own) imports the .gltf
with Blender's glTF importer and renders its sphere with Cycles (python/checks/blender_render.py).
Checked: the anisotropy imported (the Principled BSDF's Anisotropic = the glTF anisotropyStrength
and Anisotropic Rotation = anisotropyRotation / 2 pi, both to 1e-4), and the render against
Mitsuba's render of the fit: mean CIE76 dE over the lit pixels, within --tolerance. Then the same
glTF imported through slicecap's Blender add-on (python/src/slicecap/blender_addon.py), which
connects the tangent and re-maps Roughness and Anisotropic to glTF's two alphas: checked that it
set the inputs of `blender_inputs` (to 1e-4, Blender's float32) and that its render is within
--addon-tolerance of Mitsuba's.

Usage: blender_gltf.py --blender-python VENV/bin/python --mitsuba-out DIR --out DIR [--samples 16]
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time

import consumer_scene as cs
import numpy as np

from slicecap.blender_addon import blender_inputs, gltf_alphas
from slicecap.png import write_png

RENDER_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender_render.py")


def addon_set_its_inputs(gltf_path, principled) -> bool:
    """Whether the add-on's render had the tangent connected and the re-mapped inputs."""
    with open(gltf_path, encoding="utf-8") as file:
        material = json.load(file)["materials"][0]
    strength = exported_anisotropy(gltf_path)[0]
    wanted = blender_inputs(*gltf_alphas(material["pbrMetallicRoughness"]["roughnessFactor"],
                                         strength))
    return (principled["tangent_linked"]
            and abs(principled["Roughness"] - wanted.roughness) < 1e-4
            and abs(principled["Anisotropic"] - wanted.anisotropic) < 1e-4)


def exported_anisotropy(gltf_path) -> tuple[float, float]:
    with open(gltf_path, encoding="utf-8") as file:
        material = json.load(file)["materials"][0]
    extension = material.get("extensions", {}).get("KHR_materials_anisotropy", {})
    return extension.get("anisotropyStrength", 0.0), extension.get("anisotropyRotation", 0.0)


def run(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blender-python", required=True)
    parser.add_argument("--mitsuba-out", required=True, help="the mitsuba section's folder")
    parser.add_argument("--out", required=True)
    parser.add_argument("--samples", type=int, default=16)
    # From the measurement (docs/results/2026-12-02-consumer-renders.md): Cycles' Principled
    # anisotropy stretches the lobe less than glTF's mix(alpha, 1, strength^2) for the strength
    # the importer copies unchanged, up to mean dE 7.6 on the brushed metals.
    parser.add_argument("--tolerance", type=float, default=8.0, help="max mean dE (default 8)")
    # Through the add-on (docs/results/2026-12-02-consumer-renders.md, re-mapped): 0.5-3.4, and
    # 6.9 for the velvet, whose sheen is Blender's microfibre model, not glTF's.
    parser.add_argument("--addon-tolerance", type=float, default=7.5,
                        help="max mean dE through the add-on (default 7.5)")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.mitsuba_out, "mitsuba-results.json"), encoding="utf-8") as file:
        mitsuba_rows = json.load(file)
    rows = []
    for m in mitsuba_rows:
        name = m["material"]
        gltf = os.path.join(args.mitsuba_out, f"{name}.gltf")
        view_path = os.path.join(args.out, f"{name}-view.json")
        with open(view_path, "w", encoding="utf-8") as file:
            json.dump(m["view"], file)
        prefix = os.path.join(args.out, f"{name}-blender")
        started = time.perf_counter()
        subprocess.run([args.blender_python, RENDER_SCRIPT, gltf, view_path, prefix,
                        str(args.samples)], check=True, capture_output=True)
        seconds = time.perf_counter() - started
        with open(prefix + ".json", encoding="utf-8") as file:
            info = json.load(file)
        strength, rotation = exported_anisotropy(gltf)
        principled = info["principled"]
        # Every built-in anisotropic fit exports a strength above 0; a glTF without one would
        # make the comparison below pass trivially.
        imported = (strength > 0.0 and abs(principled["Anisotropic"] - strength) < 1e-4
                    and abs(principled["Anisotropic Rotation"] - rotation / (2 * math.pi)) < 1e-4)
        image8 = cs.encode(np.load(prefix + ".npy"), m["exposure"])
        write_png(prefix + ".png", image8)
        row = {"material": name, "blender": info["blender"], "seconds": round(seconds, 1),
               "principled": principled, "gltf_anisotropy": [strength, rotation],
               "anisotropy_imported": imported, **cs.judge(args.mitsuba_out, m, image8,
                                                           args.tolerance)}
        row["ok"] = row["ok"] and imported
        # Through the add-on: tangent connected, Roughness and Anisotropic re-mapped.
        subprocess.run([args.blender_python, RENDER_SCRIPT, gltf, view_path, prefix + "-addon",
                        str(args.samples), "addon"], check=True, capture_output=True)
        with open(prefix + "-addon.json", encoding="utf-8") as file:
            addon_info = json.load(file)
        addon8 = cs.encode(np.load(prefix + "-addon.npy"), m["exposure"])
        write_png(prefix + "-addon.png", addon8)
        row["addon"] = {"principled": addon_info["principled"], "lines": addon_info["addon"],
                        "inputs_set": addon_set_its_inputs(gltf, addon_info["principled"]),
                        **cs.judge(args.mitsuba_out, m, addon8, args.addon_tolerance)}
        row["ok"] = row["ok"] and row["addon"]["ok"] and row["addon"]["inputs_set"]
        rows.append(row)
        print(f"blender {name:18s} {cs.describe(row)}; Anisotropic "
              f"{principled['Anisotropic']:.4f} (glTF {strength:.4f}), Rotation "
              f"{principled['Anisotropic Rotation']:.4f} (glTF {rotation / (2 * math.pi):.4f} "
              f"turns), {seconds:.0f} s; through the add-on: mean dE "
              f"{row['addon']['delta_e']:.2f} (p95 {row['addon']['delta_e_p95']:.1f}), inputs "
              f"{'set' if row['addon']['inputs_set'] else 'NOT set'}"
              f"{'' if row['ok'] else '  FAIL'}", flush=True)
    with open(os.path.join(args.out, "blender-results.json"), "w", encoding="utf-8") as file:
        json.dump(rows, file, indent=1)
    failed = [r["material"] for r in rows if not r["ok"]]
    print(f"blender {rows[0]['blender']}: worst mean dE {max(r['delta_e'] for r in rows):.2f} "
          f"as imported (tolerance {args.tolerance:g}), "
          f"{max(r['addon']['delta_e'] for r in rows):.2f} through the add-on (tolerance "
          f"{args.addon_tolerance:g}); {'FAIL: ' + ', '.join(failed) if failed else 'ok'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
