"""The viewer's maps page reads normal.png (docs/material-viewer.md, "SVBRDF maps on a plane"):
the decoding (byte 128 is exactly 0), a flat map renders the numpy picture bit for bit as no
map, a tilt moves the highlight where the geometry of the tilt puts it, a missing or bad
normal.png is handled as documented, and headless Chromium's picture of a tilted tile matches
the numpy reference while differing from the untilted picture by far more."""

import base64
import dataclasses
import json
import math
import re

import numpy as np
import pytest
from svbrdf_maps_fixture import brushed_tiles, png_bytes, write_maps
from test_viewer_maps import (
    _chromium_screenshot,
    _mean_delta_e,
    page_albedo_table,
    page_data,
)

from slicecap import albedo_table, viewer, viewer_plane, viewer_scene
from slicecap.fitted_material import FittedMaterial
from slicecap.svbrdf_maps import read_maps, shading_normals, tilted

N = 8
PANEL = 256  # as test_viewer_maps: the page's plane panel, screenshots and references
TOLERANCE_DELTA_E = 0.5  # mean CIE76 dE over the texels' interiors, as test_viewer_maps
# (light az, light el, camera yaw, camera pitch): test_viewer_maps' two views and one with the
# light below the camera, where the plane's mirror highlight lies inside the plane.
VIEWS = ((35.0, 35.0, 0.0, 15.0), (-60.0, 25.0, 25.0, 40.0), (20.0, -25.0, 10.0, 25.0))


def pack_normals(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """normal.png's bytes for tangent-space tilts (x, y), as lib/material_export
    texture_maps.cpp writes them: lround(255 (0.5 + 0.5 c)) of (x, y, sqrt(1 - x^2 - y^2))."""
    z = np.sqrt(1.0 - x * x - y * y)
    normal = np.stack([x, y, z], axis=-1)
    # np.round rounds halves to even, lround away from zero: 127.5 (component 0) must give 128.
    return np.floor(255.0 * (0.5 + 0.5 * normal) + 0.5).astype(np.uint8)


def with_normals(maps, normals: np.ndarray):
    return dataclasses.replace(maps, images={**maps.images, "normal.png": normals})


@pytest.fixture(scope="module")
def table():
    return albedo_table.build_table()


@pytest.fixture(scope="module")
def flat_dir(tmp_path_factory):
    directory = tmp_path_factory.mktemp("normal") / "flat"
    write_maps(directory, brushed_tiles(N))  # normal.png 128, 128, 255 everywhere
    return directory


def tilt_field(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Per texel tilts: x up to 0.32, y up to 0.28 (up to 25 deg, within the fit's +-0.5), of
    both signs and on both axes, so that a swapped or mirrored axis shows."""
    rows, columns = np.indices((n, n))
    return (0.35 * np.sin(2 * np.pi * (columns + 0.5) / n),
            0.3 * np.cos(2 * np.pi * (rows + 0.5) / n))


def test_decoding_gives_exactly_flat_for_128_and_the_writer_s_tilts(flat_dir):
    maps = read_maps(flat_dir)
    assert np.all(maps.images["normal.png"] == [128, 128, 255])
    assert np.array_equal(shading_normals(maps), np.broadcast_to([0.0, 0.0, 1.0], (N, N, 3)))
    assert not tilted(maps).any()
    x, y = tilt_field(N)
    decoded = shading_normals(with_normals(maps, pack_normals(x, y)))
    truth = np.stack([x, y, np.sqrt(1 - x * x - y * y)], axis=-1)
    # The writer's rounding and the decoding's lower-edge choice: within one byte step.
    assert np.max(np.abs(decoded[..., :2] - truth[..., :2])) <= 1 / 127.5
    # So at most one step on both axes: sqrt(2) / 127.5 rad = 0.64 deg (measured 0.53).
    angle_deg = np.degrees(np.arccos(np.clip(np.sum(decoded * truth, axis=-1), -1, 1)))
    print(f"normal.png decoding: largest angle to the packed normal {angle_deg.max():.3f} deg")
    assert angle_deg.max() < 0.65


@pytest.mark.parametrize("view", [*VIEWS, (150.0, 40.0, 200.0, -30.0)],
                         ids=["front", "side", "mirror", "below"])
def test_flat_normal_map_is_bit_identical_to_no_map(flat_dir, table, view):
    maps = read_maps(flat_dir)
    with_map, _, texels = viewer_plane.render_plane_point_light(maps, table, 96, *view, 0.15)
    without, _, _ = viewer_plane.render_plane_point_light(maps, table, 96, *view, 0.15,
                                                          normal_map=False)
    assert np.count_nonzero(with_map) > 1000  # the plane is seen and lit
    assert np.array_equal(with_map, without)


GLOSSY = FittedMaterial("ggx", (0.05, 0.05, 0.05), (0.5, 0.5, 0.5), 1.0, 0.04, 0.04, 0.0)
HIGHLIGHT_VIEW = (0.0, -25.0, 0.0, 25.0)  # light below the camera: the mirror point inside
HIGHLIGHT_PANEL = 96


def _highlight_centre(image: np.ndarray) -> np.ndarray:
    """(column, row) of the specular peak: luminance-weighted centre of pixels above half max."""
    luminance = image.sum(axis=-1)
    weight = np.where(luminance > 0.5 * luminance.max(), luminance, 0.0)
    rows, columns = np.indices(luminance.shape)
    return np.array([(weight * columns).sum(), (weight * rows).sum()]) / weight.sum()


def _predicted_highlight(normal_world: np.ndarray) -> np.ndarray:
    """(column, row) of the plane pixel whose half vector is closest to the normal: where a
    mirror-like lobe peaks, from the scene's geometry alone (not the renderer's frames)."""
    light_az, light_el, yaw, pitch = HIGHLIGHT_VIEW
    origin, rays = viewer_scene.camera_rays(HIGHLIGHT_PANEL, yaw, pitch)
    t = -origin[2] / rays[..., 2]
    point = origin + t[..., None] * rays
    light = viewer_scene.LIGHT_DISTANCE * viewer_scene.orbit_direction(light_az, light_el)

    def unit(v):
        return v / np.linalg.norm(v, axis=-1, keepdims=True)

    half = unit(unit(light - point) + unit(origin - point))
    on_plane = (t > 0) & np.all(np.abs(point[..., :2]) <= viewer_plane.HALF_WIDTH, axis=-1)
    score = np.where(on_plane, half @ normal_world, -2.0)
    row, column = np.unravel_index(np.argmax(score), score.shape)
    return np.array([column, row], dtype=np.float64)


@pytest.mark.parametrize("tilt", [(0.17, 0.0), (-0.17, 0.0), (0.0, 0.17), (0.0, -0.17),
                                  (0.12, 0.12)])
def test_tilt_moves_the_highlight_where_the_tilt_says(tmp_path, table, tilt):
    """A uniform glossy tile, all its normals tilted by ~10 deg: the highlight moves from the
    flat tile's mirror point to the tilted normal's (seen from the front, tangent space = world
    x, y, z), by > 10 pixels. With the tilt's sign flipped in the decoding the highlight lands
    on the other side, ~20 pixels from the prediction."""
    directory = tmp_path / "glossy"
    write_maps(directory, [[GLOSSY] * N for _ in range(N)])
    maps = read_maps(directory)
    x, y = np.full((N, N), tilt[0]), np.full((N, N), tilt[1])
    tilted_maps = with_normals(maps, pack_normals(x, y))
    flat_image, _, _ = viewer_plane.render_plane_point_light(
        maps, table, HIGHLIGHT_PANEL, *HIGHLIGHT_VIEW, 0.0)
    tilted_image, _, _ = viewer_plane.render_plane_point_light(
        tilted_maps, table, HIGHLIGHT_PANEL, *HIGHLIGHT_VIEW, 0.0)
    flat_at = _highlight_centre(flat_image)
    tilted_at = _highlight_centre(tilted_image)
    normal = np.array([tilt[0], tilt[1], math.sqrt(1 - tilt[0] ** 2 - tilt[1] ** 2)])
    assert np.linalg.norm(flat_at - _predicted_highlight(np.array([0.0, 0.0, 1.0]))) < 2.0
    predicted = _predicted_highlight(normal)
    print(f"tilt {tilt}: highlight at {tilted_at.round(1)} px, predicted {predicted}, "
          f"flat at {flat_at.round(1)}")
    assert np.linalg.norm(predicted - flat_at) > 10.0  # the test can see a move
    assert np.linalg.norm(tilted_at - predicted) < 3.0


def _page(directory, output) -> str:
    assert viewer.run(["--maps", str(directory), "-o", str(output), "--panel-size",
                       str(PANEL)]) == 0
    return output.read_text(encoding="utf-8")


def test_page_carries_normal_png_and_counts_the_tilted_texels(tmp_path):
    directory = tmp_path / "tilted"
    write_maps(directory, brushed_tiles(N))
    x, y = tilt_field(N)
    (directory / "normal.png").write_bytes(png_bytes(pack_normals(x, y)))
    text = _page(directory, tmp_path / "view.html")
    data = page_data(text)["maps"]
    rg = np.frombuffer(base64.b64decode(data["normal_base64"]), np.uint8).reshape(N, N, 2)
    assert np.array_equal(rg, pack_normals(x, y)[..., :2])
    assert 'title="normal.png"' in text
    # The texel not fitted (brushed_tiles' marker) is not counted.
    assert f"normal.png: {N * N - 1} of {N * N} texels tilted" in text


def test_missing_normal_png_of_old_maps_is_shown_flat_with_a_note(tmp_path, flat_dir, table):
    """Maps of a fit from before the normal map (maps.json without texels_tilt_fitted) have no
    normal.png: their texels were fitted untilted, so they are shown flat, and the page says so."""
    directory = tmp_path / "old"
    write_maps(directory, brushed_tiles(N))
    (directory / "normal.png").unlink()
    text = _page(directory, tmp_path / "view.html")
    assert re.search(r'<p class="note">[^<]*normal\.png: missing \(maps of a slicecap fit '
                     r'from before the normal map\): every texel shown untilted', text)
    old = read_maps(directory)
    image, _, _ = viewer_plane.render_plane_point_light(old, table, 64, *VIEWS[0], 0.15)
    flat, _, _ = viewer_plane.render_plane_point_light(read_maps(flat_dir), table, 64,
                                                       *VIEWS[0], 0.15)
    assert np.array_equal(image, flat)


def _damage(directory, damage: str) -> str:
    path = directory / "normal.png"
    if damage == "missing, the fit wrote one":
        manifest = json.loads((directory / "maps.json").read_text())
        manifest["texels_tilt_fitted"] = N * N - 1  # as slicecap fit's maps.json
        (directory / "maps.json").write_text(json.dumps(manifest))
        path.unlink()
        return "missing (maps.json counts texels_tilt_fitted"
    if damage == "wrong size":
        path.write_bytes(png_bytes(np.full((N + 1, N, 3), 128, np.uint8)))
        return f"8 x 9 texels, maps.json says {N} x {N}"
    if damage == "grey":
        path.write_bytes(png_bytes(np.full((N, N, 1), 128, np.uint8)))
        return "1 channels, expected 3"
    path.write_bytes(path.read_bytes()[:50])  # truncated
    return "PNG"


@pytest.mark.parametrize("damage", ["missing, the fit wrote one", "wrong size", "grey",
                                    "truncated"])
def test_bad_normal_png_is_refused_naming_it(tmp_path, capsys, damage):
    directory = tmp_path / "maps"
    write_maps(directory, brushed_tiles(N))
    message = _damage(directory, damage)
    output = tmp_path / "view.html"
    assert viewer.run(["--maps", str(directory), "-o", str(output)]) == 1
    err = capsys.readouterr().err
    assert f"slicecap.viewer: {directory / 'normal.png'}" in err and message in err, err
    assert not output.exists()


# ---- headless Chromium against the numpy reference, on a tilted tile ----

@pytest.fixture(scope="module")
def tilted_page(tmp_path_factory):
    directory = tmp_path_factory.mktemp("chromium-normal") / "tilted"
    write_maps(directory, brushed_tiles(N))
    x, y = tilt_field(N)
    (directory / "normal.png").write_bytes(png_bytes(pack_normals(x, y)))
    page = directory.parent / "tilted.html"
    _page(directory, page)
    return page, directory


@pytest.mark.parametrize("view", VIEWS, ids=["front", "side", "mirror"])
def test_chromium_tilted_tile_matches_the_numpy_reference(tilted_page, tmp_path, view):
    page, directory = tilted_page
    maps = read_maps(directory)
    data = page_data(page.read_text(encoding="utf-8"))
    exposure = data["exposure"]
    table = page_albedo_table(data)
    shot = _chromium_screenshot(page, tmp_path, view, exposure)
    image, _, texels = viewer_plane.render_plane_point_light(maps, table, PANEL, *view, 0.15)
    untilted, _, _ = viewer_plane.render_plane_point_light(maps, table, PANEL, *view, 0.15,
                                                           normal_map=False)
    inner = viewer_plane.interior(texels)
    reference = viewer_plane.display_plane(image, texels, maps, exposure)
    measured = _mean_delta_e(shot, reference, inner)
    against_untilted = _mean_delta_e(
        shot, viewer_plane.display_plane(untilted, texels, maps, exposure), inner)
    print(f"tilted tile, view {view}: mean dE {measured:.4f} against the reference over "
          f"{inner.sum()} pixels (max |diff| "
          f"{np.abs(shot[inner].astype(int) - reference[inner]).max()}); against the untilted "
          f"reference {against_untilted:.3f}")
    assert measured <= TOLERANCE_DELTA_E
    # The tilt must be visible far above the tolerance, or this check could not see it.
    assert against_untilted > 10 * TOLERANCE_DELTA_E
