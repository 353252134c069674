"""The BTF directory on the desktop: what `slicecap btf` writes is read with its layout (UTIA
names, rows at the window's top), the woven texels show their own materials, and damaged
directories are refused naming the file."""

import json
import shutil
import subprocess

import numpy as np
import OpenEXR
import pytest

from slicecap import SlicecapFileError, read_abrdf_exr
from slicecap.btf import image_path, read_btf


def test_image_names_follow_the_utia_convention():
    assert image_path(0, 0) == "tv000_pv000/tl000_pl000_tv000_pv000.exr"
    assert image_path(1, 0) == "tv000_pv000/tl015_pl000_tv000_pv000.exr"
    assert image_path(80, 80) == "tv075_pv345/tl075_pl345_tv075_pv345.exr"


@pytest.fixture(scope="module")
def woven_btf(tmp_path_factory, slicecap_cli_for_module):
    directory = tmp_path_factory.mktemp("btf")
    session, out = directory / "session", directory / "btf"
    run = [str(slicecap_cli_for_module)]
    subprocess.run(
        run + ["simulate", "--material", "woven", "--session", str(session), "--frames", "8",
               "--ideal"],
        check=True, capture_output=True,
    )
    subprocess.run(
        run + ["btf", str(session), "-o", str(out), "--resolution", "4", "--threads", "2"],
        check=True, capture_output=True,
    )
    return out


def test_reads_the_texture_the_cpp_side_wrote(woven_btf):
    btf = read_btf(woven_btf)
    assert btf.resolution == 4
    assert btf.images.shape == (81, 81, 4, 4, 3)
    assert btf.window_mm == (-20.0, -20.0, 20.0, 20.0)
    np.testing.assert_array_equal(
        btf.average.values, read_abrdf_exr(woven_btf / "average.exr").values
    )
    # Texel (0, 0) lies on a weft cell (red satin), texel (1, 0) on a warp cell (blue satin).
    red_cell, blue_cell = btf.texel(0, 0).values, btf.texel(1, 0).values
    assert red_cell[..., 0].sum() > red_cell[..., 2].sum()
    assert blue_cell[..., 2].sum() > blue_cell[..., 0].sum()
    assert json.loads((woven_btf / "btf.json").read_text())["failed_texels"] == 0


def test_texels_outside_the_window_are_refused(woven_btf):
    btf = read_btf(woven_btf)
    np.testing.assert_array_equal(btf.texel(3, 2).values, btf.images[:, :, 2, 3].astype(np.float32))
    np.testing.assert_array_equal(btf.texel(np.int64(1), 0).values, btf.texel(1, 0).values)
    # -1 used to be numpy's last column: another texel's table without a word.
    with pytest.raises(IndexError, match=r"texel column -1 is outside 0..3 \(the BTF is 4 x 4\)"):
        btf.texel(-1, 0)
    with pytest.raises(IndexError, match="texel row 4 is outside 0..3"):
        btf.texel(0, 4)
    with pytest.raises(TypeError, match="texel column must be a whole number, got 1.5"):
        btf.texel(1.5, 0)
    with pytest.raises(TypeError, match="texel row must be a whole number, got True"):
        btf.texel(0, True)


def test_a_resolution_the_images_do_not_have_is_named(woven_btf, tmp_path):
    inconsistent = tmp_path / "inconsistent"
    shutil.copytree(woven_btf, inconsistent)
    manifest = json.loads((inconsistent / "btf.json").read_text())
    # 6561 images of 1024 x 1024: 38 GiB, which numpy failed to allocate before any was read.
    manifest["resolution"] = 1024
    (inconsistent / "btf.json").write_text(json.dumps(manifest))
    with pytest.raises(SlicecapFileError) as raised:
        read_btf(inconsistent)
    assert str(raised.value) == (
        f"{inconsistent / image_path(0, 0)}: 4 x 4 texels, the manifest says 1024 x 1024"
    )


def test_a_damaged_directory_is_refused_naming_the_file(woven_btf, tmp_path):
    broken = tmp_path / "broken"
    shutil.copytree(woven_btf, broken)
    victim = broken / image_path(40, 7)
    whole = victim.read_bytes()
    victim.write_bytes(whole[:-1])
    with pytest.raises(SlicecapFileError) as raised:
        read_btf(broken)
    assert str(raised.value) == (
        f"{victim}: cannot read EXR: its pixel data is truncated or corrupt"
    )
    victim.unlink()
    with pytest.raises(SlicecapFileError, match=f"{victim}: cannot read EXR: No such file"):
        read_btf(broken)
    victim.write_bytes(whole)
    (broken / "btf.json").write_text('{"format": "something else", "resolution": 4}')
    with pytest.raises(SlicecapFileError, match="btf.json: field 'format'"):
        read_btf(broken)
    with pytest.raises(SlicecapFileError, match="not a BTF directory"):
        read_btf(tmp_path / "nowhere")


def rewrite_image(path, change):
    """Rewrites one BTF image with `change` applied to its (N, N, 3) float32 pixels."""
    with OpenEXR.File(str(path), separate_channels=True) as file:
        channels = file.channels()
        pixels = np.stack([channels[c].pixels.astype(np.float32) for c in "RGB"], axis=-1)
    change(pixels)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {c: pixels[..., i].copy() for i, c in enumerate("RGB")}) as file:
        file.write(str(path))


def test_a_non_finite_texel_is_refused_naming_the_image_and_texel(woven_btf, tmp_path):
    broken = tmp_path / "broken"
    shutil.copytree(woven_btf, broken)
    victim = broken / image_path(3, 5)

    def put_nan(pixels):
        pixels[1, 2, 1] = np.nan

    rewrite_image(victim, put_nan)
    with pytest.raises(SlicecapFileError) as raised:
        read_btf(broken)
    assert str(raised.value) == (
        f"{victim}: non-finite value (as a half float) at column 2, row 1, channel G"
    )

    def put_beyond_half(pixels):
        pixels[0, 3, 2] = 1e6  # a float image: infinity once read as half

    shutil.copy(woven_btf / image_path(3, 5), victim)
    rewrite_image(victim, put_beyond_half)
    with pytest.raises(SlicecapFileError, match="at column 3, row 0, channel B"):
        read_btf(broken)


@pytest.mark.parametrize(
    "content, problem",
    [
        (b"[4]", "not a JSON object but list"),
        (b"null", "not a JSON object but NoneType"),
        (b"\x80\x81 binary", "not JSON"),
        (b"[" * 200_000, "not JSON: nested too deep"),
        (b'{"format": "slicecap-btf", "resolution": true}', "field 'resolution'"),
        (b'{"format": "slicecap-btf", "resolution": 4}', "field 'window_mm'"),
        (
            b'{"format": "slicecap-btf", "resolution": 4, "window_mm": [20, -20, -20, 20]}',
            "field 'window_mm'",
        ),
        (
            b'{"format": "slicecap-btf", "resolution": 4, "window_mm": [-20, -20, 20, "20"]}',
            "field 'window_mm'",
        ),
        (
            b'{"format": "slicecap-btf", "resolution": 4, "window_mm": [-20, -20, 20, 20], '
            b'"average": 3}',
            "field 'average' is not a file name",
        ),
    ],
)
def test_a_corrupt_manifest_is_refused_naming_it(tmp_path, content, problem):
    (tmp_path / "btf.json").write_bytes(content)
    with pytest.raises(SlicecapFileError) as raised:
        read_btf(tmp_path)
    assert str(raised.value).startswith(f"{tmp_path / 'btf.json'}: {problem}")
