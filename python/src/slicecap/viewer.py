"""slicecap-viewer TABLE.exr [--material MATERIAL.json] -o VIEW.html, or
slicecap-viewer --maps MAPS_DIR -o VIEW.html, or slicecap-viewer DIR -o VIEW.html (an export
folder or a MAPS_DIR, slicecap.viewer_export), each also with --serve [PORT] (slicecap.viewer_serve)
(or python -m slicecap.viewer ...)

Writes one self-contained HTML page (docs/material-viewer.md): the fitted material of
`slicecap fit` and the measured table side by side on a sphere and a cloth-like sheet, drawn by
WebGL under a point light the viewer drags plus a constant environment, beside the table's
81 x 81 layout picture; or the SVBRDF maps of `slicecap fit BTF_DIR` on a plane
(slicecap.viewer_maps_page). Everything is inline (script, shaders, the table as base64 float32, the
picture as a data: URI): the page needs no network. Exit codes: 0 success, 1 failure (a message
naming the input), 2 bad usage.
"""

import argparse
import base64
import html
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from slicecap import viewer_scene
from slicecap.abrdf_exr import SlicecapFileError
from slicecap.fitted_material import (
    SHEEN_ALBEDO_MAX_ROUGHNESS,
    SHEEN_ALBEDO_MIN_ROUGHNESS,
    FittedMaterial,
    has_coat,
    has_sheen,
    read_fit_document,
    sheen_albedo_table,
)
from slicecap.grid import (
    DIRECTION_COUNT,
    GRID_DIRECTIONS_DEG,
    RING_FIRST_INDEX,
    Brdf,
    to_directions_deg,
)
from slicecap.image_metrics import EXPOSURE_PERCENTILE, to_8bit
from slicecap.interpolation import evaluate
from slicecap.materials import load_material
from slicecap.paths import StrPath, same_file, write_replacing
from slicecap.png import encode_png
from slicecap.render import render_sphere_point_light
from slicecap.viewer_export import find_contents
from slicecap.viewer_maps_page import build_maps_page
from slicecap.viewer_serve import LOOPBACK, make_server, page_url, serve_until_interrupted
from slicecap.viewer_template import fill_template

LAYOUT_SCALE = 4
_RING_LINE = (72, 72, 72)
DEFAULT_PANEL_SIZE = 320
_EXPOSURE_PROBE_SIZE = 96
_LAYOUT_HTML = """<p>The measured table, 81 x 81 (row = light direction, column = view direction,
  Bonn order), times cos(theta_light), normalised to its maximum, sRGB:</p>
  <img id="layout" alt="the 81 x 81 layout of the measured table" src="{{LAYOUT_URI}}">
  """
# The usage names what started it: the console script, or python -m (then this module is __main__).
PROG = "python -m slicecap.viewer" if __name__ == "__main__" else "slicecap-viewer"


def table_brdf(values: np.ndarray) -> Brdf:
    """brdf(to_light, to_view) of an (81, 81, 3) table: (N, 3) unit vectors in the table's frame
    to (N, 3) RGB, interpolated as slicecap.interpolation (the page's tableBrdf)."""
    def brdf(to_light: np.ndarray, to_view: np.ndarray) -> np.ndarray:
        return evaluate(values, to_directions_deg(to_light), to_directions_deg(to_view))

    return brdf


def layout_offset(index: int) -> int:
    """The pixel offset of a direction's row or column in layout_picture: whole entries plus one
    line per ring boundary before it (lib/render layout_image.cpp)."""
    return index * LAYOUT_SCALE + int(np.searchsorted(RING_FIRST_INDEX, index, side="right")) - 1


def layout_picture(values: np.ndarray) -> np.ndarray:
    """The table as `slicecap preview` lays it out (lib/render layoutImage): row = light, column =
    view, both in Bonn order, LAYOUT_SCALE pixels an entry and a grey line between the six rings;
    each entry the paper's 8-bit encoding (times cos(theta_light), over the table's largest such
    value, clipped, sRGB). ValueError for a table with no positive value."""
    cos_light = np.cos(np.radians(GRID_DIRECTIONS_DEG[:, 0]))
    weighted = np.asarray(values, dtype=np.float64) * cos_light[:, None, None]
    peak = float(weighted.max())
    if not peak > 0.0:
        raise ValueError("the table has no positive value to show")
    encoded = to_8bit(weighted, peak)
    side = DIRECTION_COUNT * LAYOUT_SCALE + len(RING_FIRST_INDEX) - 1
    image = np.full((side, side, 3), _RING_LINE, dtype=np.uint8)
    offsets = [layout_offset(i) for i in range(DIRECTION_COUNT)]
    for light, y in enumerate(offsets):
        row = np.repeat(encoded[light], LAYOUT_SCALE, axis=0)  # (81 * scale, 3)
        for dy in range(LAYOUT_SCALE):
            for view, x in enumerate(offsets):
                image[y + dy, x : x + LAYOUT_SCALE] = row[view * LAYOUT_SCALE]
    return image


def default_exposure(brdf: Brdf, albedo: np.ndarray) -> float:
    """1 / the EXPOSURE_PERCENTILE-th percentile of the table's sphere under the default view:
    the highlight just reaches white (as slicecap.render's pictures)."""
    d = viewer_scene.DEFAULTS
    image, mask = render_sphere_point_light(
        brdf, albedo, _EXPOSURE_PROBE_SIZE, d["light_az"], d["light_el"], d["yaw"], d["pitch"],
        d["env"],
    )
    level = float(np.percentile(image[mask], EXPOSURE_PERCENTILE))
    return 1.0 / level if level > 0.0 else 1.0


def _base64_floats(values: ArrayLike) -> str:
    return base64.b64encode(np.asarray(values, dtype="<f4").tobytes()).decode("ascii")


def sheen_albedo_data() -> dict:
    """The sheen's directional albedo E (slicecap.fitted_material.sheen_albedo_table, lib/fit's
    table) for the shader's khr_materials_sheen scaling: computed here, not in the page, so that
    the page draws with the same E as the numpy model and lib/fit; row j = roughness node j
    (uniform from min_roughness to max_roughness), column i = cosine i / (cosines - 1)."""
    table = sheen_albedo_table()
    return {
        "base64": _base64_floats(table),
        "cosines": int(table.shape[1]),
        "roughnesses": int(table.shape[0]),
        "min_roughness": SHEEN_ALBEDO_MIN_ROUGHNESS,
        "max_roughness": SHEEN_ALBEDO_MAX_ROUGHNESS,
    }


def _material_rows(material: FittedMaterial, document: dict) -> str:
    def show(value: float | tuple[float, ...]) -> str:
        if isinstance(value, tuple):
            return " / ".join(f"{v:.4g}" for v in value)
        return f"{value:.4g}"

    names = ["diffuse_albedo", "specular_f0", "specular_f90", "alpha_tangent", "alpha_bitangent",
             "tangent_deg"]
    if has_sheen(material.model):
        names += ["sheen_colour", "sheen_roughness"]
    if has_coat(material.model):
        names += ["coat_weight", "coat_alpha"]
    rows = [f"<tr><td>model</td><td>{html.escape(material.model)}</td></tr>"]
    rows += [f"<tr><td>{n}</td><td>{show(getattr(material, n))}</td></tr>" for n in names]
    if has_sheen(material.model):
        rows.append(f"<tr><td>sheen_form</td><td>{html.escape(material.sheen_form)}</td></tr>")
    metrics = document.get("metrics") or {}
    if isinstance(metrics.get("delta_e"), (int, float)):
        rows.append(f"<tr><td>fit vs table</td><td>dE {metrics['delta_e']:.2f}</td></tr>")
    return "<p>Fitted material:</p><table>" + "".join(rows) + "</table>"


def _labels(size: int, material_name: str | None, table_name: str) -> str:
    texts = [
        (0, 0, f"fitted: {material_name}" if material_name else "no fit given (--material)"),
        (size, 0, f"measured: {table_name}"),
        (0, size, "fitted, cloth" if material_name else ""),
        (size, size, "measured, cloth"),
    ]
    return "\n".join(
        f'<div class="label" style="left:{x + 6}px; top:{y + 4}px">{html.escape(t)}</div>'
        for x, y, t in texts
        if t
    )


def build_page(
    table_path: StrPath, material_path: StrPath | None = None, panel_size: int = DEFAULT_PANEL_SIZE
) -> str:
    """The page's HTML text. Raises SlicecapFileError naming the file that is not an ABRDF table
    or not a completed `slicecap fit` JSON."""
    table = load_material(table_path)
    if not np.any(table.values > 0.0):
        # Nothing would show, and no exposure can be chosen: said, not drawn black.
        raise SlicecapFileError(f"{os.fspath(table_path)}: the table has no positive value to show")
    brdf = table_brdf(table.values)
    table_albedo = viewer_scene.directional_albedo(brdf)
    table_name = os.path.basename(os.fspath(table_path))
    data = {
        "panel_size": panel_size,
        "scene": viewer_scene.page_constants(),
        "exposure": default_exposure(brdf, table_albedo),
        "table": {
            "name": table_name,
            "values_base64": _base64_floats(table.values),
            "albedo_base64": _base64_floats(table_albedo),
        },
        "material": None,
    }
    material_html, material_name = "", None
    if material_path is not None:
        material, document = read_fit_document(material_path)
        parameters = {
            name: getattr(material, name)
            for name in FittedMaterial.__dataclass_fields__
            if name != "model"
        }
        material_file = os.path.basename(os.fspath(material_path))
        material_data: dict = {
            "name": material_file,
            "model": material.model,
            "parameters": parameters,
            "albedo_base64": _base64_floats(viewer_scene.directional_albedo(material.evaluate)),
        }
        if has_sheen(material.model) and material.sheen_form == "khr_materials_sheen":
            material_data["sheen_albedo"] = sheen_albedo_data()
        data["material"] = material_data
        material_html = _material_rows(material, document)
        material_name = f"{material_file} ({material.model})"
    layout_uri = "data:image/png;base64," + base64.b64encode(
        encode_png(layout_picture(table.values))
    ).decode("ascii")
    return fill_template({
        "{{LABELS}}": _labels(panel_size, material_name, table_name),
        "{{SIDE_LEFT}}": str(2 * panel_size),
        "{{TITLE}}": html.escape(table_name + (f" / {material_name}" if material_name else "")),
        "{{SIDE_DETAILS}}": _LAYOUT_HTML.replace("{{LAYOUT_URI}}", layout_uri) + material_html,
    }, data)


def _parse(argv: Sequence[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Write (or serve on 127.0.0.1) a self-contained HTML viewer of a measured "
        "ABRDF table and its fitted material (slicecap fit) on a sphere and a cloth under a "
        "light you drag, or of the SVBRDF maps of a texture (slicecap fit BTF_DIR) on a plane; "
        "given a directory (a `slicecap export` folder or a MAPS_DIR), what it holds.",
    )
    parser.add_argument(
        "source", nargs="?", metavar="TABLE.exr|DIR",
        help="the ABRDF EXR (81 x 81 table), or a directory: a `slicecap export` folder (the "
        "table its manifest lists first, the daemon's fit of it, and a page for each SVBRDF "
        "maps folder inside) or a MAPS_DIR")
    parser.add_argument(
        "--maps", metavar="MAPS_DIR",
        help="instead of a table: the SVBRDF maps `slicecap fit BTF_DIR -o MAPS_DIR` wrote, "
        "shown on a plane")
    parser.add_argument("--material", help="the fit of the table: slicecap fit's MATERIAL.json")
    parser.add_argument(
        "-o", "--output",
        help="the page to write (.html); a directory's further pages go beside it as "
        "VIEW-NAME.html (required unless --serve)")
    parser.add_argument(
        "--serve", nargs="?", const=0, type=int, metavar="PORT",
        help="serve the page(s) on http://127.0.0.1:PORT/ until Ctrl-C (a free port if no PORT "
        "is given); put it after TABLE.exr|DIR")
    parser.add_argument(
        "--panel-size", type=int, default=DEFAULT_PANEL_SIZE,
        help=f"pixels per rendering panel, 64..1024 (default {DEFAULT_PANEL_SIZE})",
    )
    return parser.parse_args(argv)


@dataclass(frozen=True)
class Page:
    """One page to write or serve: `name` is "" for the main page (-o VIEW.html, URL /), else
    the page's part of VIEW-NAME.html and /NAME.html."""

    name: str
    text: str


def _usage_error(args: argparse.Namespace) -> str | None:
    if not 64 <= args.panel_size <= 1024:
        return "--panel-size must be in 64..1024"
    if args.output is None and args.serve is None:
        return "give -o VIEW.html, --serve [PORT] or both"
    if args.serve is not None and not 0 <= args.serve <= 65535:
        return "--serve PORT must be in 0..65535 (0: a free port)"
    if (args.source is None) == (args.maps is None):
        return "give either TABLE.exr (or a directory) or --maps MAPS_DIR"
    if args.maps is not None and args.material is not None:
        return "--material is for a table, not --maps"
    if args.source is not None and os.path.isdir(args.source) and args.material is not None:
        return "--material is for TABLE.exr; a directory's fit is found in it"
    return None


def _directory_pages(directory: str, panel_size: int) -> tuple[list[Page], list[str]]:
    """The pages of a directory (viewer_export.find_contents) and what to tell the user."""
    contents = find_contents(directory)
    pages, notes = [], []
    if contents.table is not None:
        pages.append(Page("", build_page(contents.table, contents.material, panel_size)))
        fit = f" with its fit {contents.material}" if contents.material else " (no fit found)"
        notes.append(f"table {contents.table}{fit}, chosen by {contents.found_by}")
    for other in contents.other_tables:
        notes.append(f"also in the export: {other} (slicecap-viewer {other} -o VIEW.html)")
    for maps in contents.maps_dirs:
        name = "" if not pages else os.path.basename(os.path.normpath(maps))
        pages.append(Page(name, build_maps_page(maps, panel_size)))
        notes.append(f"SVBRDF maps {maps}")
    if not contents.maps_dirs:
        for texture in contents.texture_dirs:
            notes.append(f"texture {texture}: no maps yet (`slicecap btf {texture} -o BTF` then "
                         f"`slicecap fit BTF -o {texture[: -len('-texture')]}-maps`)")
    return pages, notes


def _build_pages(args: argparse.Namespace) -> tuple[list[Page], list[str]]:
    if args.maps is not None:
        return [Page("", build_maps_page(args.maps, args.panel_size))], []
    if os.path.isdir(args.source):
        return _directory_pages(args.source, args.panel_size)
    return [Page("", build_page(args.source, args.material, args.panel_size))], []


def page_path(output: str, page: Page) -> str:
    """Where a page is written: -o's path for the main page, VIEW-NAME.html beside it else."""
    if not page.name:
        return output
    stem, extension = os.path.splitext(output)
    return f"{stem}-{page.name}{extension or '.html'}"


def _write_pages(output: str, pages: list[Page]) -> None:
    for page in pages:
        target = page_path(output, page)

        def write(temporary: str, text: str = page.text) -> None:
            with open(temporary, "w", encoding="utf-8") as file:
                file.write(text)

        try:
            write_replacing(target, write)
        except OSError as e:
            raise SlicecapFileError(f"{target}: cannot write ({e.strerror})") from None
        print(f"wrote {target} ({len(page.text) // 1024} KiB)")


def _serve(pages: list[Page], port: int) -> int:
    served = {("/" + page.name + ".html" if page.name else "/"): page.text.encode("utf-8")
              for page in pages}
    try:
        server = make_server(served, port)
    except OSError as e:
        print(f"slicecap.viewer: port {port} on {LOOPBACK}: cannot serve ({e.strerror})",
              file=sys.stderr)
        return 1
    with server:
        serve_until_interrupted(server, [page_url(server, path) for path in served])
    print("stopped", flush=True)
    return 0


def run(argv: Sequence[str]) -> int:
    args = _parse(argv)
    usage = _usage_error(args)
    if usage is not None:
        print(f"slicecap.viewer: {usage}", file=sys.stderr)
        return 2
    for role, path in (("table", args.source), ("material", args.material)):
        if args.output and path and same_file(args.output, path):
            print(f"slicecap.viewer: -o {args.output} is the {role}: it would be overwritten",
                  file=sys.stderr)
            return 2
    try:
        pages, notes = _build_pages(args)
        for note in notes:
            print(note)
        if args.output is not None:
            _write_pages(args.output, pages)
    except SlicecapFileError as e:
        print(f"slicecap.viewer: {e}", file=sys.stderr)
        return 1
    return _serve(pages, args.serve) if args.serve is not None else 0


def main() -> None:
    sys.exit(run(sys.argv[1:]))


if __name__ == "__main__":
    main()
