"""The viewer's SVBRDF plane (docs/material-viewer.md): page-writing CPU time at several map sizes
and the albedo table's error against the exact per-texel integration it replaces.

    .venv/bin/python python/bench/viewer_maps_figures.py [--sizes 8 64 128]

Maps: the tests' "brushed tiles" fixture (every texel distinct) and a "mixed" one whose texels
sweep the roughness and anisotropy strength between the table's nodes. Prints Markdown
(docs/results/2026-12-02-material-viewer.md).
"""

import argparse
import math
import pathlib
import resource
import sys
import tempfile

import numpy as np

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPOSITORY / "python" / "tests"))
from svbrdf_maps_fixture import brushed_tiles, write_maps  # noqa: E402

from slicecap import albedo_table, viewer, viewer_plane, viewer_scene  # noqa: E402
from slicecap.fitted_material import FittedMaterial  # noqa: E402
from slicecap.grid import GRID_DIRECTIONS_DEG, to_unit_vectors  # noqa: E402
from slicecap.svbrdf_maps import read_maps, texel_materials  # noqa: E402


def mixed_texels(n: int) -> list[list[FittedMaterial | None]]:
    """n x n texels: alpha_bitangent from 0.01 to 0.7 down the rows, the strength of the
    anisotropy from 0 to 0.95 and the tangent from 0 to 170 deg across the columns."""
    rows: list[list[FittedMaterial | None]] = []
    for y in range(n):
        alpha_b = 0.01 + 0.69 * (y / max(n - 1, 1)) ** 2
        row: list[FittedMaterial | None] = []
        for x in range(n):
            strength = 0.95 * x / max(n - 1, 1)
            alpha_t = alpha_b + (1 - alpha_b) * strength * strength
            row.append(FittedMaterial("ggx", (0.2, 0.1, 0.05), (0.6, 0.5, 0.4), 0.95, alpha_t,
                                      alpha_b, 170.0 * x / max(n - 1, 1)))
        rows.append(row)
    return rows


def table_error(maps_dir: pathlib.Path) -> tuple[np.ndarray, np.ndarray]:
    """Per fitted texel and grid direction (<= 75 deg) the table's albedo and the exact one
    (viewer_scene.directional_albedo of the texel's decoded material), (T, 81, 3) each."""
    maps = read_maps(maps_dir)
    table = albedo_table.build_table()
    views = to_unit_vectors(GRID_DIRECTIONS_DEG)
    looked_up, exact = [], []
    for index, material in enumerate(m for row in texel_materials(maps) for m in row):
        if material is None:
            continue
        texel = np.full(len(views), index)
        looked_up.append(viewer_plane.environment_albedo(maps, table, texel, views))
        exact.append(viewer_scene.directional_albedo(material.evaluate))
    return np.asarray(looked_up), np.asarray(exact)


def cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[8, 64, 128])
    arguments = parser.parse_args()
    with tempfile.TemporaryDirectory() as temporary:
        root = pathlib.Path(temporary)
        print("| maps | texels | page-writing CPU | page size |\n| --- | --- | --- | --- |")
        for n in arguments.sizes:
            directory = root / f"tiles{n}"
            write_maps(directory, brushed_tiles(n))
            page = root / f"tiles{n}.html"
            before = cpu_seconds()
            assert viewer.run(["--maps", str(directory), "-o", str(page)]) == 0
            print(f"| brushed tiles | {n} x {n} | {cpu_seconds() - before:.1f} s | "
                  f"{page.stat().st_size / 1024:.0f} KiB |")
        print("\n| maps | texels | abs error mean / max | relative error mean / max |\n"
              "| --- | --- | --- | --- |")
        mixed = mixed_texels(8)
        for name, materials, rows in (("brushed tiles (alpha_b 0.08)", brushed_tiles(8), 8),
                                      ("mixed, alpha_b 0.01-0.07", mixed, 3),
                                      ("mixed, alpha_b 0.14-0.70", mixed, -5)):
            directory = root / name.split(" ")[0].strip(",")
            write_maps(directory, materials)
            looked_up, exact = table_error(directory)
            keep = slice(0, rows * 8) if rows > 0 else slice(rows * 8, None)
            looked_up, exact = looked_up[keep], exact[keep]
            error = np.abs(looked_up - exact)
            relative = error / np.maximum(exact, 1e-6)
            print(f"| {name} | {len(exact)} fitted x 81 directions | {error.mean():.2e} / "
                  f"{error.max():.2e} | {relative.mean():.2%} / {relative.max():.2%} |")
    assert math.isfinite(float(error.max()))


if __name__ == "__main__":
    main()
