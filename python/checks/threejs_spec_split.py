"""How far three.js 0.187 draws an exported glTF from the fit, split by cause, on the Bonn grid
(issue 46): for each material, its table is fitted and exported by the given `slicecap`, the
fit's own table is made (`slicecap generate MATERIAL.json`), and the .gltf's material is
tabulated by threejs_brdf.py with every three.js deviation, with each one alone put back to the
specification's form, and with none (which is the specification: gltf_spec_brdf.py's figure);
each compared with the fit's table by `slicecap compare` (mean dE). Prints a Markdown table.
With --cumulative the deviations are put back one after another, in the order of DEVIATIONS,
each column keeping the ones before it put back.

    .venv/bin/python python/checks/threejs_spec_split.py [--slicecap build/app/slicecap]
        [--cumulative] [NAME...]
"""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from gltf_spec_brdf import REPOSITORY, gltf_brdf  # noqa: E402
from threejs_brdf import DEVIATIONS, threejs_brdf  # noqa: E402

from slicecap.abrdf_exr import write_abrdf_exr  # noqa: E402
from slicecap.grid import tabulate  # noqa: E402


def run(cli: str, *arguments: object) -> str:
    return subprocess.run([cli, *map(str, arguments)], check=True, capture_output=True,
                          text=True).stdout


def delta_e(cli: str, fit_table: pathlib.Path, brdf, scratch: pathlib.Path) -> float:
    write_abrdf_exr(scratch, tabulate(brdf))
    return float(json.loads(run(cli, "compare", fit_table, scratch, "--json"))["delta_e"])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slicecap", default=str(REPOSITORY / "build/app/slicecap"))
    parser.add_argument("--gltf-dir", type=pathlib.Path,
                        help="read NAME.gltf and NAME.json from here instead of fitting")
    parser.add_argument("--cumulative", action="store_true")
    parser.add_argument("materials", nargs="*", help="default: every built-in material")
    args = parser.parse_args()
    cli = args.slicecap
    names = args.materials or [line.split()[0] for line in
                               run(cli, "generate", "--list").splitlines()]
    columns = list(DEVIATIONS)
    header = "+ {} by the spec" if args.cumulative else "only {} by the spec"
    print("| material | spec (Charlie) | three.js 0.187 | "
          + " | ".join(header.format(c) for c in columns) + " |")
    print("|---" * (3 + len(columns)) + "|")
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        for name in names:
            material, gltf, fit_table = (root / f"{name}{s}" for s in
                                         (".json", ".gltf", "-fit.exr"))
            if args.gltf_dir:
                material, gltf = args.gltf_dir / f"{name}.json", args.gltf_dir / f"{name}.gltf"
            else:
                table = root / f"{name}.exr"
                run(cli, "generate", name, "-o", table)
                run(cli, "fit", table, "-o", material, "--gltf", gltf)
            run(cli, "generate", material, "-o", fit_table)
            gltf_material = json.loads(gltf.read_text())["materials"][0]
            scratch = root / "scratch.exr"
            figures = [delta_e(cli, fit_table, gltf_brdf(gltf_material), scratch),
                       delta_e(cli, fit_table, threejs_brdf(gltf_material), scratch)]
            for i, column in enumerate(columns):
                kept = (columns[i + 1:] if args.cumulative
                        else [d for d in DEVIATIONS if d != column])
                figures.append(delta_e(cli, fit_table, threejs_brdf(gltf_material, kept),
                                       scratch))
            print(f"| {name} | " + " | ".join(f"{f:.2f}" for f in figures) + " |", flush=True)


if __name__ == "__main__":
    main()
