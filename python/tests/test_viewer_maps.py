"""The viewer's SVBRDF-maps plane (python -m slicecap.viewer --maps, docs/material-viewer.md):
the maps decode to the materials they were packed from, the page is self-contained and carries
the maps' bytes, bad input is refused naming the file, and headless Chromium's picture of the
plane matches the numpy reference (slicecap.viewer_plane) while a reference that ignores the
anisotropy direction does not."""

import base64
import dataclasses
import json
import re
import shutil
import subprocess

import numpy as np
import pytest
from conftest import find_slicecap_cli
from svbrdf_maps_fixture import brushed_tiles, png_bytes, write_maps
from test_viewer import parse  # the HTML collector: elements close, scripts by id

from slicecap import albedo_table, viewer, viewer_plane, viewer_scene
from slicecap.albedo_table import AlbedoTable
from slicecap.fitted_material import FittedMaterial
from slicecap.grid import GRID_DIRECTIONS_DEG, to_unit_vectors
from slicecap.image_metrics import delta_e_8bit
from slicecap.png import read_png
from slicecap.svbrdf_maps import decode_parameters, read_maps, texel_materials

N = 8
PANEL = 256
TOLERANCE_DELTA_E = 0.5  # mean CIE76 dE over the plane's interior, as the table viewer's check
VIEWS = ((35.0, 35.0, 0.0, 15.0), (-60.0, 25.0, 25.0, 40.0))


@pytest.fixture(scope="module")
def maps_dir(tmp_path_factory):
    directory = tmp_path_factory.mktemp("maps") / "tiles"
    write_maps(directory, brushed_tiles(N))
    return directory


@pytest.fixture(scope="module")
def page(maps_dir):
    output = maps_dir.parent / "view.html"
    assert viewer.run(["--maps", str(maps_dir), "-o", str(output), "--panel-size",
                       str(PANEL)]) == 0
    return output


def page_data(text: str) -> dict:
    return json.loads(re.search(r'<script id="slicecap-data"[^>]*>(.*?)</script>', text,
                                re.S).group(1))


def page_albedo_table(data: dict) -> AlbedoTable:
    """The albedo table the page carries, as the shader reads it."""
    table = data["maps"]["albedo_table"]
    values = np.frombuffer(base64.b64decode(table["base64"]), "<f4").reshape(
        table["height"], table["width"], 2)
    return AlbedoTable(values, table["diffuse_weight"])


def test_maps_decode_to_the_materials_they_were_packed_from(maps_dir):
    truth = brushed_tiles(N)
    decoded = texel_materials(read_maps(maps_dir))
    for y in range(N):
        for x in range(N):
            want, got = truth[y][x], decoded[y][x]
            assert (want is None) == (got is None), (y, x)
            if want is None:
                continue
            # 8-bit quantisation: ~1 % on colours and alphas, ~0.5 deg on the tangent.
            np.testing.assert_allclose(got.diffuse_albedo, want.diffuse_albedo, rtol=0.03)
            np.testing.assert_allclose(got.specular_f0, want.specular_f0, rtol=0.02)
            assert got.specular_f90 == pytest.approx(want.specular_f90, abs=0.003)
            assert got.alpha_tangent == pytest.approx(want.alpha_tangent, rel=0.02)
            assert got.alpha_bitangent == pytest.approx(want.alpha_bitangent, rel=0.02)
            turn = (got.tangent_deg - want.tangent_deg + 90) % 180 - 90
            assert abs(turn) < 0.6, (y, x, got.tangent_deg, want.tangent_deg)


def test_page_is_self_contained_and_carries_the_maps_bytes(page, maps_dir):
    text = page.read_text(encoding="utf-8")
    assert {"slicecap-data", "vertex-shader", "fragment-shader"} <= set(parse(text).scripts)
    for value in re.findall(r'(?:src|href)="([^"]*)"', text):
        assert value.startswith("data:"), value[:60]
    assert not re.search(r"https?://|//cdn|@import", text)
    assert "{{" not in text
    data = page_data(text)["maps"]
    maps = read_maps(maps_dir)
    base = np.frombuffer(base64.b64decode(data["base_base64"]), np.uint8).reshape(N, N, 4)
    assert np.array_equal(base[..., :3], maps.images["base_color.png"])
    assert np.array_equal(base[..., 3], maps.images["mask.png"][..., 0])
    assert data["resolution"] == N and data["ior_f0"] == pytest.approx(maps.ior_f0)
    assert "texel not fitted (mask.png 0): 1 of 64" in text


def _break(directory, name):
    if name == "not a MAPS_DIR":
        (directory / "maps.json").unlink()
        return directory / "maps.json"
    path = directory / name
    if name == "missing":
        path = directory / "anisotropy.png"
        path.unlink()
    elif name == "truncated":
        path = directory / "specular.png"
        path.write_bytes(path.read_bytes()[:60])
    elif name == "wrong size":
        path = directory / "metallic_roughness.png"
        path.write_bytes(png_bytes(np.zeros((N, N + 1, 3), np.uint8)))
    return path


@pytest.mark.parametrize("damage,message", [
    ("not a MAPS_DIR", "missing: "),
    ("missing", "missing"),
    ("truncated", "PNG"),
    ("wrong size", f"9 x 8 texels, maps.json says {N} x {N}"),
])
def test_bad_maps_are_refused_naming_the_file(tmp_path, capsys, damage, message):
    directory = tmp_path / "maps"
    write_maps(directory, brushed_tiles(N))
    path = _break(directory, damage)
    output = tmp_path / "view.html"
    assert viewer.run(["--maps", str(directory), "-o", str(output)]) == 1
    err = capsys.readouterr().err
    assert f"slicecap.viewer: {path}" in err and message in err, err
    assert not output.exists()


def test_folder_that_is_not_a_directory_is_refused(tmp_path, capsys):
    output = tmp_path / "view.html"
    assert viewer.run(["--maps", str(tmp_path / "none"), "-o", str(output)]) == 1
    assert f"{tmp_path / 'none'}: not a directory" in capsys.readouterr().err
    assert not output.exists()


# ---- headless Chromium against the numpy reference ----

def _chromium_screenshot(page, tmp_path, view, exposure) -> np.ndarray:
    binary = shutil.which("chromium")
    if binary is None:
        pytest.skip("chromium is not installed (Debian's `chromium`, "
                    "scripts/deps/browser.list): the real-browser check cannot run")
    light_az, light_el, yaw, pitch = view
    url = (f"file://{page}#light={light_az:g},{light_el:g}&camera={yaw:g},{pitch:g}"
           f"&env=0.15&exposure={exposure!r}")
    shot = tmp_path / "shot.png"
    flags = ["--headless", "--no-sandbox", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--hide-scrollbars", "--force-device-scale-factor=1",
             "--disable-gpu-sandbox", f"--window-size={PANEL + 400},{PANEL}",
             f"--user-data-dir={tmp_path / 'profile'}"]
    run = subprocess.run([binary, *flags, f"--screenshot={shot}", url], capture_output=True,
                         text=True, timeout=180)
    assert run.returncode == 0 and shot.exists(), run.stderr[-500:]
    return read_png(shot)[:PANEL, :PANEL]


def _mean_delta_e(a: np.ndarray, b: np.ndarray, mask: np.ndarray) -> float:
    return float(np.mean(delta_e_8bit(a[mask], b[mask])))


def compare_with_chromium(page, maps_dir, tmp_path, view) -> tuple[float, dict[str, float]]:
    """The mean dE of the screenshot against the reference over the plane's texel interiors,
    and against two wrong references (the anisotropy direction ignored: every tangent along x;
    every tangent turned by 90 deg); asserts the texels not fitted show the marker."""
    maps = read_maps(maps_dir)
    data = page_data(page.read_text(encoding="utf-8"))
    exposure = data["exposure"]
    albedos = page_albedo_table(data)
    shot = _chromium_screenshot(page, tmp_path, view, exposure)
    image, _, texels = viewer_plane.render_plane_point_light(maps, albedos, PANEL, *view, 0.15)
    reference = viewer_plane.display_plane(image, texels, maps, exposure)
    inner = viewer_plane.interior(texels)
    measured = _mean_delta_e(shot, reference, inner)
    unfitted = inner & ~maps.fitted.reshape(-1)[np.maximum(texels, 0)]
    assert np.all(shot[unfitted] == viewer_plane.MARKER_SRGB8)
    controls = {}
    for name, anisotropy in (("ignored", _tangent_along_x), ("turned", _tangent_turned)):
        wrong_maps = dataclasses.replace(maps, images={
            **maps.images, "anisotropy.png": anisotropy(maps.images["anisotropy.png"])})
        wrong, _, _ = viewer_plane.render_plane_point_light(wrong_maps, albedos, PANEL, *view,
                                                            0.15)
        controls[name] = _mean_delta_e(
            shot, viewer_plane.display_plane(wrong, texels, maps, exposure), inner)
    print(f"maps plane {maps_dir.name}, view {view}: mean dE {measured:.4f} over "
          f"{inner.sum()} pixels, max |diff| "
          f"{np.abs(shot[inner].astype(int) - reference[inner]).max()}; controls: anisotropy "
          f"direction ignored {controls['ignored']:.3f}, turned 90 deg {controls['turned']:.3f}")
    return measured, controls


@pytest.mark.parametrize("view", VIEWS, ids=["front", "side"])
def test_chromium_plane_matches_the_numpy_reference(page, maps_dir, tmp_path, view):
    measured, controls = compare_with_chromium(page, maps_dir, tmp_path, view)
    assert measured <= TOLERANCE_DELTA_E
    # The controls must be above the tolerance, or this check could not see those errors.
    assert min(controls.values()) > TOLERANCE_DELTA_E
    assert not read_maps(maps_dir).fitted.all(), "the fixture is expected to hold a marker"


def test_chromium_plane_of_maps_slicecap_fit_wrote(tmp_path):
    """The maps of the real pipeline (a woven BTF of 8 x 8 texels, simulated with 12 frames a
    sweep: ~17 s): the C++'s PNGs are read and the plane matches its reference."""
    if shutil.which("chromium") is None:
        pytest.skip("chromium is not installed (Debian's `chromium`): the real-browser check "
                    "cannot run")
    cli = str(find_slicecap_cli())
    session, btf, maps_dir = tmp_path / "session", tmp_path / "btf", tmp_path / "woven-maps"
    for command in (
        ["simulate", "--material", "woven", "--session", session, "--ideal", "--frames", "12"],
        ["btf", session, "-o", btf, "--resolution", "8", "--threads", "2"],
        ["fit", btf, "-o", maps_dir, "--threads", "2"],
    ):
        subprocess.run([cli, *map(str, command)], check=True, capture_output=True)
    page = tmp_path / "woven.html"
    assert viewer.run(["--maps", str(maps_dir), "-o", str(page), "--panel-size",
                       str(PANEL)]) == 0
    measured, _ = compare_with_chromium(page, maps_dir, tmp_path, VIEWS[0])
    assert measured <= TOLERANCE_DELTA_E
    # No control here: this small, quickly simulated woven fit is nearly round (wrong tangents
    # measured at dE 0.3-0.5); the fixture's maps above are the negative control.


def _tangent_along_x(anisotropy: np.ndarray) -> np.ndarray:
    flat = anisotropy.copy()
    flat[..., 0], flat[..., 1] = 255, 128
    return flat


def _tangent_turned(anisotropy: np.ndarray) -> np.ndarray:
    """(cos, sin) -> (-sin, cos): every tangent turned by 90 deg, the strength kept."""
    turned = anisotropy.copy()
    turned[..., 0], turned[..., 1] = 255 - anisotropy[..., 1], anisotropy[..., 0]
    return turned


def test_decoding_reads_the_anisotropy_direction(maps_dir):
    """The decoding itself: the tangent turns across the columns as the maps were packed."""
    tangent = decode_parameters(read_maps(maps_dir))["tangent_deg"]
    assert np.all(np.diff(tangent[0]) > 15)


def test_maps_larger_than_the_viewer_takes_are_refused(tmp_path, capsys):
    directory = tmp_path / "big"
    side = viewer_plane.MAX_RESOLUTION + 1
    write_maps(directory, [[brushed_tiles(2)[0][0]] * side] * side)
    output = tmp_path / "view.html"
    assert viewer.run(["--maps", str(directory), "-o", str(output)]) == 1
    assert (f"{directory / 'maps.json'}: {side} x {side} texels; the viewer shows maps up to"
            in capsys.readouterr().err)
    assert not output.exists()


@pytest.mark.parametrize("arguments", [["t.exr", "--maps", "m"], ["--maps", "m", "--material",
                                                                 "f.json"], []])
def test_table_and_maps_together_or_neither_is_bad_usage(tmp_path, arguments):
    assert viewer.run([*arguments, "-o", str(tmp_path / "v.html")]) == 2


def _tiled(tiles: list[list], side: int) -> list[list]:
    """side x side texels made of the few distinct ones of `tiles`, each a square block."""
    block = side // len(tiles)
    return [[tiles[y // block][x // block] for x in range(side)] for y in range(side)]


def test_maps_of_slicecap_fit_s_default_size_are_written_self_contained(tmp_path):
    """128 x 128 texels (slicecap fit's default, docs/reference/cli.md) of 16 distinct ones:
    the page is written, carries every texel's bytes and no URL, and its albedo texture stays
    within OpenGL ES 3.0's promised 2048 x 2048."""
    side = 128
    directory = tmp_path / "default-size"
    write_maps(directory, _tiled(brushed_tiles(4), side))
    output = tmp_path / "view.html"
    assert viewer.run(["--maps", str(directory), "-o", str(output)]) == 0
    text = output.read_text(encoding="utf-8")
    for value in re.findall(r'(?:src|href)="([^"]*)"', text):
        assert value.startswith("data:"), value[:60]
    assert not re.search(r"https?://|//cdn|@import", text)
    data = page_data(text)["maps"]
    assert data["resolution"] == side
    shape = np.frombuffer(base64.b64decode(data["shape_base64"]), np.uint8).reshape(side, side, 4)
    maps = read_maps(directory)
    assert np.array_equal(shape[..., :3], maps.images["anisotropy.png"])
    table = data["albedo_table"]
    assert max(table["width"], table["height"], side) <= 2048


def _mixed_texels() -> list[list]:
    """3 x 4 texels between the albedo table's nodes: alpha_b 0.11..0.6 down the rows, the
    anisotropy strength and the tangent across the columns."""
    return [[FittedMaterial("ggx", (0.2, 0.1, 0.05), (0.6, 0.5, 0.4), 0.95,
                            a + (1 - a) * s * s, a, tangent)
             for s, tangent in ((0.0, 10.0), (0.37, 55.0), (0.71, 100.0), (0.93, 160.0))]
            for a in (0.11, 0.29, 0.6)]


def test_albedo_table_matches_the_per_texel_integration(tmp_path):
    """The table's albedo (slicecap.albedo_table, as the page looks it up) against
    viewer_scene.directional_albedo of each texel's decoded material at the 81 grid
    directions: within 4 % (measured 3.1 % at most, at 75 deg where the integration itself
    varies by 7 % around the ring of an isotropic lobe; docs/results/2026-12-02-material-viewer.md).
    Lobes narrower than alpha ~0.1 are left out: the 45 x 90 quadrature does not resolve them,
    per texel or in the table."""
    materials = _mixed_texels()
    materials = [*materials, materials[0]]  # square: 4 x 4
    directory = tmp_path / "mixed"
    write_maps(directory, materials)
    maps = read_maps(directory)
    table = albedo_table.build_table()
    views = to_unit_vectors(GRID_DIRECTIONS_DEG)
    for index, material in enumerate(m for row in texel_materials(maps) for m in row):
        exact = viewer_scene.directional_albedo(material.evaluate)
        looked_up = viewer_plane.environment_albedo(maps, table, np.full(len(views), index),
                                                    views)
        np.testing.assert_allclose(looked_up, exact, rtol=0.04, err_msg=str(material))
