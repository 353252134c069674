"""three.js renders the exported glTF (scripts/consumer-check, section "threejs"): Debian's headless
Chromium opens threejs_page.html, which loads each material's .gltf with three's GLTFLoader
(npm `three`, pinned in tools/consumers, served from its node_modules by a server on 127.0.0.1: no
network) and renders its sphere in the scene of consumer_scene.py; the pixels are compared with
Mitsuba's render of the same fit (section "mitsuba", whose folder this reads): mean CIE76 dE over
the lit pixels, within --tolerance.

Usage: threejs_gltf.py --mitsuba-out DIR --out DIR [--three tools/consumers/node_modules/three]
"""

import argparse
import base64
import functools
import http.server
import json
import os
import re
import subprocess
import sys
import threading

import consumer_scene as cs
import numpy as np

from slicecap.png import write_png

PAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "threejs_page.html")
# As python/checks/viewer_chromium.py: SwiftShader WebGL, headless, one device pixel per CSS one.
CHROMIUM_FLAGS = [
    "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
    "--disable-gpu-sandbox", "--force-device-scale-factor=1", "--window-size=400,400",
    "--virtual-time-budget=60000",
]


class _Handler(http.server.SimpleHTTPRequestHandler):
    """/page.html, /three/... (node_modules/three), /m/NAME/model.gltf and /m/NAME/view.json."""

    def __init__(self, *args, three, files, **kwargs):
        self.three, self.files = three, files
        super().__init__(*args, **kwargs)

    def translate_path(self, path):
        path = path.split("?", 1)[0]
        if path == "/page.html":
            return PAGE
        if path.startswith("/three/") and ".." not in path:
            return os.path.join(self.three, path[len("/three/"):])
        return self.files.get(path, "/nonexistent")

    def log_message(self, *args):
        pass


def serve(three: str, files: dict):
    handler = functools.partial(_Handler, three=three, files=files)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def render(chromium: str, profile: str, url: str, size: int):
    """(8-bit image, material summary) from the page, or raises RuntimeError with its error."""
    dom = subprocess.run([chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "--dump-dom",
                          url], capture_output=True, text=True, timeout=300).stdout
    if 'data-rendered="yes"' not in dom:
        error = re.search(r'<pre id="error">(.*?)</pre>', dom, re.S)
        raise RuntimeError(f"three.js page did not render: "
                           f"{error.group(1).strip() if error else dom[-800:]}")
    pixels = base64.b64decode(re.search(r'<pre id="pixels">(.*?)</pre>', dom, re.S).group(1))
    image = np.frombuffer(pixels, np.uint8).reshape(size, size, 4)[::-1, :, :3]
    summary = re.search(r'data-material="([^"]*)"', dom).group(1).replace("&quot;", '"')
    return image, json.loads(summary)


def run(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mitsuba-out", required=True, help="the mitsuba section's folder")
    parser.add_argument("--out", required=True)
    parser.add_argument("--three", default="tools/consumers/node_modules/three")
    parser.add_argument("--chromium", default="chromium")
    # From the measurement (docs/results/2026-12-02-consumer-renders.md): at most 2.84, brass.
    parser.add_argument("--tolerance", type=float, default=4.0, help="max mean dE (default 4)")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.mitsuba_out, "mitsuba-results.json"), encoding="utf-8") as file:
        mitsuba_rows = json.load(file)
    with open(os.path.join(args.three, "package.json"), encoding="utf-8") as file:
        version = json.load(file)["version"]
    files, rows = {}, []
    server = serve(os.path.abspath(args.three), files)
    try:
        for m in mitsuba_rows:
            name = m["material"]
            gltf = os.path.abspath(os.path.join(args.mitsuba_out, f"{name}.gltf"))
            view = dict(m["view"], exposure=m["exposure"],
                        sphere_node=cs.read_sphere(gltf).node_index)
            view_path = os.path.abspath(os.path.join(args.out, f"{name}-view.json"))
            with open(view_path, "w", encoding="utf-8") as file:
                json.dump(view, file)
            files[f"/m/{name}/model.gltf"], files[f"/m/{name}/view.json"] = gltf, view_path
            url = f"http://127.0.0.1:{server.server_address[1]}/page.html?m={name}"
            image, material = render(args.chromium, os.path.abspath(
                os.path.join(args.out, "chromium-profile")), url, view["size_px"])
            write_png(os.path.join(args.out, f"{name}-threejs.png"), image)
            row = {"material": name, "three": version, "loaded_material": material,
                   **cs.judge(args.mitsuba_out, m, image, args.tolerance)}
            rows.append(row)
            print(f"threejs {name:18s} {cs.describe(row)}; loaded {material}"
                  f"{'' if row['ok'] else '  FAIL'}", flush=True)
    finally:
        server.shutdown()
    with open(os.path.join(args.out, "threejs-results.json"), "w", encoding="utf-8") as file:
        json.dump(rows, file, indent=1)
    failed = [r["material"] for r in rows if not r["ok"]]
    print(f"threejs {version}: worst mean dE {max(r['delta_e'] for r in rows):.2f} (tolerance "
          f"{args.tolerance:g}); {'FAIL: ' + ', '.join(failed) if failed else 'ok'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
