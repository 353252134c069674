"""The material exports on every built-in material: the fit, the glTF export's BRDF against the fit,
the Khronos validator's findings, MaterialX's validation, Mitsuba's BSDF against the fit.

    .venv/bin/python python/bench/material_export_figures.py [--slicecap build/app/slicecap]

Needs scripts/build (the slicecap command), scripts/python-env (MaterialX, Mitsuba) and
scripts/consumers-install (the glTF validator). Prints a Markdown table
(docs/results/2026-12-02-material-export.md).
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPOSITORY / "python" / "tests"))
from material_export_support import mitsuba_ratios, sheen_stand_in  # noqa: E402


def validator_counts(path: pathlib.Path) -> str:
    run = subprocess.run(["node", REPOSITORY / "tools/consumers/validate-gltf.mjs", path],
                         capture_output=True, text=True, check=False)
    issues = json.loads(run.stdout)["issues"]
    return f"{issues['numErrors']}/{issues['numWarnings']}/{issues['numInfos']}"


def materialx_valid(path: pathlib.Path) -> str:
    import MaterialX as mx

    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    doc.setDataLibrary(library)
    return "valid" if doc.validate()[0] else "INVALID"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slicecap", default=str(REPOSITORY / "build/app/slicecap"))
    args = parser.parse_args()
    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    names = [line.split()[0] for line in subprocess.run(
        [args.slicecap, "generate", "--list"], capture_output=True, text=True, check=True
    ).stdout.splitlines() if line.strip()]
    print("| material | fit model | fit dE | glTF vs fit dE | validator E/W/I (.gltf) | MaterialX |"
          " Mitsuba/fit median | p5 | p95 | glTF losses |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        root = pathlib.Path(folder)
        for name in names:
            table, material = root / f"{name}.exr", root / f"{name}.json"
            gltf, mtlx, xml = root / f"{name}.gltf", root / f"{name}.mtlx", root / f"{name}.xml"
            subprocess.run([args.slicecap, "generate", name, "-o", table], check=True,
                           capture_output=True)
            subprocess.run([args.slicecap, "fit", table, "-o", material, "--gltf", gltf, "--mtlx",
                            mtlx, "--mitsuba", xml], check=True, capture_output=True)
            fitted = json.loads(material.read_text())
            extras = json.loads(gltf.read_text())["asset"]["extras"]
            # A sheen fit's snippet has a GGX stand-in for the sheen: the ratio is to the fit's
            # diffuse + GGX plus that stand-in (its own mismatch to the sheen is in its loss).
            stand_in = sheen_stand_in(xml.read_text())
            ratios = mitsuba_ratios(mi, mi.load_file(str(xml)), fitted["parameters"],
                                    extra=stand_in)
            gltf_losses = sorted({loss["kind"] for loss in extras["slicecap_conversion_losses"]})
            sheen = ""
            if fitted["model"] == "ggx+sheen":
                sheen = " (Mitsuba: sheen " + ("dropped)" if stand_in is None else "stand-in)")
            print(f"| {name} | {fitted['model']} | {fitted['metrics']['delta_e']:.2f} | "
                  f"{extras['slicecap_gltf_versus_fit']['delta_e']:.2f} | "
                  f"{validator_counts(gltf)} | "
                  f"{materialx_valid(mtlx)} | {np.median(ratios):.3f} | "
                  f"{np.percentile(ratios, 5):.3f} | {np.percentile(ratios, 95):.3f} | "
                  f"{', '.join(gltf_losses) or '-'}{sheen} |")


if __name__ == "__main__":
    main()
