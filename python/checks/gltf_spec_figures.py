"""The glTF export of every built-in material measured by the specifications (issue 46): for each
material of `slicecap generate --list`, its table is fitted and exported by the given `slicecap`,
the fit's own table is generated from the fit's JSON (`slicecap generate MATERIAL.json`), and the
.gltf's material, evaluated by python/checks/gltf_spec_brdf.py (Charlie and Ashikhmin sheen
visibility), is compared with it; the CLI's own figure (`asset.extras.slicecap_gltf_versus_fit`)
beside. Prints a Markdown table.

    .venv/bin/python python/checks/gltf_spec_figures.py [--slicecap build/app/slicecap]
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from gltf_spec_brdf import REPOSITORY, gltf_versus_fit_delta_e  # noqa: E402


def run(cli: str, *arguments: object) -> None:
    subprocess.run([cli, *map(str, arguments)], check=True, capture_output=True, text=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slicecap", default=str(REPOSITORY / "build/app/slicecap"))
    parser.add_argument("materials", nargs="*", help="default: every built-in material")
    args = parser.parse_args()
    cli = args.slicecap
    listing = subprocess.run([cli, "generate", "--list"], check=True, capture_output=True,
                             text=True).stdout
    names = args.materials or [line.split()[0] for line in listing.splitlines()]
    print("| material | fit model | fit dE | glTF (spec, Charlie) vs fit dE | "
          "glTF (spec, Ashikhmin) vs fit dE | the export's own check |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        for name in names:
            table, material, gltf, fit_table = (root / f"{name}{s}" for s in
                                                (".exr", ".json", ".gltf", "-fit.exr"))
            run(cli, "generate", name, "-o", table)
            run(cli, "fit", table, "-o", material, "--gltf", gltf)
            run(cli, "generate", material, "-o", fit_table)
            fitted = json.loads(material.read_text())
            own = json.loads(gltf.read_text())["asset"]["extras"]["slicecap_gltf_versus_fit"]
            charlie = gltf_versus_fit_delta_e(gltf, fit_table, cli, "charlie")
            ashikhmin = gltf_versus_fit_delta_e(gltf, fit_table, cli, "ashikhmin")
            print(f"| {name} | {fitted['model']} | {fitted['metrics']['delta_e']:.2f} | "
                  f"{charlie:.2f} | {ashikhmin:.2f} | {own['delta_e']:.2f} |", flush=True)


if __name__ == "__main__":
    main()
