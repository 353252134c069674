"""three.js's render of an export split by cause: the consumer check's three.js page renders each
material with threejs_spec.js's changes made one after another (none, + the Charlie visibility,
+ the sheen's own albedo, + 1 - max_value(F), + no multiple-scattering compensation = all), each
compared with Mitsuba's reference (consumer_scene.mitsuba_reference) and with the exact render of
the fit (exact_fit_render.py, pixel centres). Prints a Markdown table.

    .venv/bin/python python/checks/threejs_render_split.py --consumer-out DIR [NAME...]

DIR is a scripts/consumer-check output whose mitsuba/ and threejs/ folders exist.
"""

import argparse
import json
import os
import sys

import consumer_scene as cs
import threejs_gltf
from exact_fit_render import render_exact

from slicecap.fitted_material import read_fitted_material

PARTS = ("visibility", "sheen_albedo", "diffuse_dimming", "multiscatter")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--consumer-out", required=True)
    parser.add_argument("--three", default="tools/consumers/node_modules/three")
    parser.add_argument("--chromium", default="chromium")
    parser.add_argument("materials", nargs="*", help="default: every row of the mitsuba section")
    args = parser.parse_args()
    mitsuba = os.path.join(args.consumer_out, "mitsuba")
    out = os.path.join(args.consumer_out, "threejs-split")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(mitsuba, "mitsuba-results.json"), encoding="utf-8") as file:
        rows = [r for r in json.load(file) if not args.materials or r["material"] in args.materials]
    steps = [PARTS[:i] for i in range(len(PARTS) + 1)]
    print("| material | against | stock | spec, no change | "
          + " | ".join(f"+ {p}" for p in PARTS) + " |")
    print("|---|---|---|---|" + "---|" * len(PARTS))
    files: dict = {}
    server = threejs_gltf.serve(os.path.abspath(args.three), files)
    try:
        for row in rows:
            name = row["material"]
            gltf = os.path.abspath(os.path.join(mitsuba, f"{name}.gltf"))
            view = dict(row["view"], exposure=row["exposure"],
                        sphere_node=cs.read_sphere(gltf).node_index)
            view_path = os.path.abspath(os.path.join(out, f"{name}-view.json"))
            with open(view_path, "w", encoding="utf-8") as file:
                json.dump(view, file)
            files[f"/m/{name}/model.gltf"], files[f"/m/{name}/view.json"] = gltf, view_path
            fit = read_fitted_material(os.path.join(mitsuba, f"{name}.json"))
            exact = cs.encode(render_exact(fit.evaluate, gltf, row["view"]), row["exposure"])
            reference, against = cs.mitsuba_reference(mitsuba, row,
                                                      os.path.join(mitsuba, f"{name}.json"))
            queries = [""] + ["&spec=1&parts=" + ",".join(step) for step in steps]
            images = [threejs_gltf.render(args.chromium, os.path.abspath(
                os.path.join(out, "chromium-profile")),
                f"http://127.0.0.1:{server.server_address[1]}/page.html?m={name}{query}",
                view["size_px"])[0] for query in queries]
            for label, ref in ((f"Mitsuba's {against}", reference), ("the exact fit", exact)):
                figures = [cs.compare_8bit(ref, image, cs.lit_mask(ref) | cs.lit_mask(image))[
                    "delta_e"] for image in images]
                print(f"| {name} | {label} | " + " | ".join(f"{f:.2f}" for f in figures) + " |",
                      flush=True)
    finally:
        server.shutdown()


if __name__ == "__main__":
    sys.exit(main())
