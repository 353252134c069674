"""python -m slicecap.render: the picture, the metrics it prints, and its failures."""

import numpy as np
import pytest
from mitsuba_support import phong

from slicecap import read_abrdf_exr, render, tabulate, write_abrdf_exr
from slicecap.png import read_png_size


def tiny_run(args, capsys):
    pytest.importorskip("mitsuba", reason="mitsuba is not installed (requirements-mitsuba.txt)")
    code = render.run(args + ["--size", "16", "--spp", "2", "--variant", "scalar_rgb"])
    return code, capsys.readouterr()


def test_a_material_against_itself_scores_zero_and_another_does_not(tmp_path, capsys):
    write_abrdf_exr(
        tmp_path / "glossy.exr",
        tabulate(phong([0.3, 0.2, 0.1], [0.3] * 3, 10)),
        {"material": "glossy"},
    )
    write_abrdf_exr(tmp_path / "matte.exr", tabulate(phong([0.3, 0.2, 0.1], [0.0] * 3, 1)))
    code, out = tiny_run(
        [
            str(tmp_path / "glossy.exr"),
            "--reference",
            str(tmp_path / "glossy.exr"),
            "-o",
            str(tmp_path / "same.png"),
        ],
        capsys,
    )
    assert code == 0, out.err
    assert out.out.count("dE   0.00") == 4 and out.out.count("PSNR 100.00 dB") == 4
    width, height = read_png_size(tmp_path / "same.png")
    assert width == 8 + 4 * (16 + 8) and height > 3 * 16

    code, out = tiny_run(
        [
            str(tmp_path / "matte.exr"),
            "--reference",
            str(tmp_path / "glossy.exr"),
            "-o",
            str(tmp_path / "different.png"),
        ],
        capsys,
    )
    assert code == 0, out.err
    assert "dE   0.00" not in out.out

    code, out = tiny_run([str(tmp_path / "glossy.exr"), "-o", str(tmp_path / "alone.png")], capsys)
    assert code == 0 and "dE" not in out.out
    assert read_png_size(tmp_path / "alone.png")[1] < height


def test_a_bad_input_fails_with_the_readers_message(tmp_path, capsys):
    (tmp_path / "junk.exr").write_text("not an EXR")
    code, out = tiny_run([str(tmp_path / "junk.exr"), "-o", str(tmp_path / "x.png")], capsys)
    assert code == 1
    assert f"{tmp_path / 'junk.exr'}: cannot read EXR" in out.err
    with pytest.raises(SystemExit) as usage:
        render.run([str(tmp_path / "junk.exr")])
    assert usage.value.code == 2


def test_an_output_that_is_an_input_is_bad_usage_and_leaves_it_alone(tmp_path, capsys):
    table = tabulate(phong([0.3, 0.2, 0.1], [0.3] * 3, 10))
    write_abrdf_exr(tmp_path / "glossy.exr", table)
    write_abrdf_exr(tmp_path / "truth.exr", table)
    (tmp_path / "link.exr").symlink_to(tmp_path / "truth.exr")
    material, truth, link = (str(tmp_path / n) for n in ("glossy.exr", "truth.exr", "link.exr"))
    for args, role in (
        ([material, "-o", material], "material"),
        ([material, "--reference", truth, "-o", link], "reference"),
    ):
        assert render.run(args) == 2
        assert f"is the {role}: it would be overwritten" in capsys.readouterr().err
    np.testing.assert_array_equal(read_abrdf_exr(tmp_path / "glossy.exr").values, table)
    np.testing.assert_array_equal(read_abrdf_exr(tmp_path / "truth.exr").values, table)


def test_a_seed_mitsuba_cannot_take_is_bad_usage(tmp_path, capsys):
    write_abrdf_exr(tmp_path / "glossy.exr", tabulate(phong([0.3, 0.2, 0.1], [0.3] * 3, 10)))
    for seed in ("-1", str(2**32)):
        code, out = tiny_run(
            [str(tmp_path / "glossy.exr"), "-o", str(tmp_path / "x.png"), "--seed", seed], capsys
        )
        assert code == 2
        assert "--seed must be in 0..4294967295" in out.err
    code, out = tiny_run(
        [str(tmp_path / "glossy.exr"), "-o", str(tmp_path / "x.png"), "--seed", str(2**32 - 1)],
        capsys,
    )
    assert code == 0, out.err


def test_a_folder_the_picture_cannot_go_to_is_said_before_anything_is_read(tmp_path, capsys):
    # The material is junk: a check made after reading or rendering would report it instead.
    (tmp_path / "junk.exr").write_text("not an EXR")
    missing = tmp_path / "no-such-folder" / "x.png"
    code, out = tiny_run([str(tmp_path / "junk.exr"), "-o", str(missing)], capsys)
    assert code == 1
    assert f"{missing}: the folder {missing.parent} does not exist or is not writable" in out.err
    assert "cannot read EXR" not in out.err
