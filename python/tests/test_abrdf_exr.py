"""ABRDF EXR in Python: exact round trips, the C++ reader's rejections and messages, and files
that cross between the C++ and the Python side."""

import json
import os
import subprocess
import sys
import tempfile
import threading

import numpy as np
import OpenEXR
import pytest

from slicecap import Abrdf, SlicecapFileError, read_abrdf_exr, write_abrdf_exr

GOOD_ATTRIBUTES = {"slicecap:layout": "bonn81", "slicecap:quantity": "brdf"}


def ramp_table() -> np.ndarray:
    return (np.arange(81 * 81 * 3, dtype=np.float32) * 1e-3 + 1e-7).reshape(81, 81, 3)


def write_raw_exr(path, width, height, channels, attributes):
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    header.update(attributes)
    pixels = {c: np.full((height, width), 0.5, dtype=np.float32) for c in channels}
    with OpenEXR.File(header, pixels) as file:
        file.write(str(path))


def read_error(path) -> str:
    with pytest.raises(SlicecapFileError) as raised:
        read_abrdf_exr(path)
    return str(raised.value)


def test_round_trips_values_and_attributes_exactly(tmp_path):
    table = ramp_table()
    write_abrdf_exr(tmp_path / "t.exr", table, {"method": "B", "material": "felt"})
    back = read_abrdf_exr(tmp_path / "t.exr")
    np.testing.assert_array_equal(back.values, table)
    assert back.attributes["layout"] == "bonn81"
    assert back.attributes["quantity"] == "brdf"
    assert back.attributes["method"] == "B"
    assert back.attributes["material"] == "felt"
    assert back.attributes["version"]


def test_rows_are_lights_and_columns_are_views(tmp_path):
    table = np.zeros((81, 81, 3), dtype=np.float32)
    table[2, 8] = (1, 2, 3)
    write_abrdf_exr(tmp_path / "t.exr", table)
    with OpenEXR.File(str(tmp_path / "t.exr"), separate_channels=True) as file:
        red = file.channels()["R"].pixels
    assert red[2, 8] == 1.0, "row 2 (light), column 8 (view)"
    assert red[8, 2] == 0.0


def test_rejects_a_wrong_size(tmp_path):
    write_raw_exr(tmp_path / "small.exr", 81, 80, "RGB", GOOD_ATTRIBUTES)
    error = read_error(tmp_path / "small.exr")
    assert error.startswith(str(tmp_path / "small.exr") + ": ")
    assert "must be 81 x 81 (light rows x view columns), got 80 x 81" in error


def test_rejects_a_missing_channel(tmp_path):
    write_raw_exr(tmp_path / "rg.exr", 81, 81, "RG", GOOD_ATTRIBUTES)
    error = read_error(tmp_path / "rg.exr")
    assert error == f"{tmp_path / 'rg.exr'}: ABRDF EXR has no channel B (needs R, G, B)"


def test_rejects_another_layout_no_layout_and_another_quantity(tmp_path):
    write_raw_exr(
        tmp_path / "utia.exr",
        81,
        81,
        "RGB",
        {"slicecap:layout": "utia", "slicecap:quantity": "brdf"},
    )
    assert read_error(tmp_path / "utia.exr").endswith(
        'header attribute slicecap:layout is "utia", expected "bonn81"'
    )
    write_raw_exr(tmp_path / "plain.exr", 81, 81, "RGB", {})
    assert read_error(tmp_path / "plain.exr").endswith(
        'missing header attribute slicecap:layout (expected "bonn81"); ' "is this a slicecap ABRDF?"
    )
    write_raw_exr(
        tmp_path / "abrdf.exr",
        81,
        81,
        "RGB",
        {"slicecap:layout": "bonn81", "slicecap:quantity": "abrdf"},
    )
    assert 'slicecap:quantity is "abrdf"' in read_error(tmp_path / "abrdf.exr")


def write_past_the_package(path, table):
    """The package's writer refuses the tables these tests need: written through OpenEXR itself."""
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    header.update(GOOD_ATTRIBUTES)
    channels = {c: table[..., i].astype(np.float32) for i, c in enumerate("RGB")}
    with OpenEXR.File(header, channels) as file:
        file.write(str(path))


def test_rejects_non_finite_values(tmp_path):
    table = np.zeros((81, 81, 3), dtype=np.float32)
    table[5, 6, 2] = np.nan
    write_past_the_package(tmp_path / "nan.exr", table)
    assert read_error(tmp_path / "nan.exr").endswith(
        "non-finite value at light 5, view 6, channel B"
    )


def test_rejects_negative_values_but_reads_negative_zero(tmp_path):
    # A BRDF is never negative; a table from another tool holding one would render as negative
    # light. The message is the C++ reader's (tests/io/abrdf_exr_test.cpp).
    table = ramp_table()
    table[2, 9, 0] = -0.0
    write_past_the_package(tmp_path / "zero.exr", table)
    np.testing.assert_array_equal(read_abrdf_exr(tmp_path / "zero.exr").values, table)
    table[4, 11, 1] = -0.25
    write_past_the_package(tmp_path / "negative.exr", table)
    assert read_error(tmp_path / "negative.exr") == (
        f"{tmp_path / 'negative.exr'}: negative value -0.25 at light 4, view 11, channel G "
        "(a BRDF is never negative)"
    )


@pytest.mark.parametrize(
    "bad, said",
    [
        (np.inf, "non-finite value at light 7, view 3, channel G"),
        (-1e-6, "negative value -1e-06 at light 7, view 3, channel G (a BRDF is never negative)"),
    ],
)
def test_refuses_to_write_a_table_the_reader_would_refuse(tmp_path, bad, said):
    table = ramp_table()
    table[7, 3, 1] = bad
    table[9, 0, 0] = bad
    with pytest.raises(SlicecapFileError) as raised:
        write_abrdf_exr(tmp_path / "bad.exr", table)
    assert str(raised.value) == f"{tmp_path / 'bad.exr'}: not written: a {said}"
    assert not (tmp_path / "bad.exr").exists()


def test_rejects_missing_and_corrupt_files(tmp_path):
    assert read_error(tmp_path / "none.exr") == (
        f"{tmp_path / 'none.exr'}: cannot read EXR: No such file or directory"
    )
    (tmp_path / "folder.exr").mkdir()
    assert read_error(tmp_path / "folder.exr") == (
        f"{tmp_path / 'folder.exr'}: is a directory, not an ABRDF EXR"
    )
    (tmp_path / "junk.exr").write_text("this is not an EXR file")
    assert read_error(tmp_path / "junk.exr") == (
        f"{tmp_path / 'junk.exr'}: cannot read EXR: not an OpenEXR file (no EXR magic number)"
    )
    (tmp_path / "empty.exr").write_bytes(b"")
    assert read_error(tmp_path / "empty.exr").endswith("not an OpenEXR file (an empty file)")
    write_abrdf_exr(tmp_path / "whole.exr", ramp_table())
    whole = (tmp_path / "whole.exr").read_bytes()
    (tmp_path / "head.exr").write_bytes(whole[:200])
    assert read_error(tmp_path / "head.exr") == (
        f"{tmp_path / 'head.exr'}: cannot read EXR: its header is truncated or corrupt"
    )
    for cut in (len(whole) // 2, len(whole) - 1):
        (tmp_path / "cut.exr").write_bytes(whole[:cut])
        assert read_error(tmp_path / "cut.exr") == (
            f"{tmp_path / 'cut.exr'}: cannot read EXR: its pixel data is truncated or corrupt"
        )
    damaged = bytearray(whole)
    damaged[-40:-32] = bytes(b ^ 0xFF for b in damaged[-40:-32])
    (tmp_path / "damaged.exr").write_bytes(damaged)
    assert read_error(tmp_path / "damaged.exr").endswith("pixel data is truncated or corrupt")
    with pytest.raises(SlicecapFileError, match="no/such/dir.exr: cannot write EXR"):
        write_abrdf_exr(tmp_path / "no" / "such" / "dir.exr", ramp_table())


def test_a_damaged_file_is_said_once_and_prints_nothing_else(tmp_path, capfd):
    # OpenEXR printed a line per chunk to stderr and a warning to stdout (into a script's own
    # output) before the error said the same.
    write_abrdf_exr(tmp_path / "whole.exr", ramp_table())
    whole = (tmp_path / "whole.exr").read_bytes()
    (tmp_path / "cut.exr").write_bytes(whole[: len(whole) // 2])
    capfd.readouterr()
    assert read_error(tmp_path / "cut.exr").endswith("pixel data is truncated or corrupt")
    assert read_abrdf_exr(tmp_path / "whole.exr").values.shape == (81, 81, 3)
    printed = capfd.readouterr()
    assert (printed.out, printed.err) == ("", "")
    print("after", file=sys.stderr)
    print("after")
    assert capfd.readouterr() == ("after\n", "after\n"), "stdout and stderr are back"


def test_only_openexr_damage_lines_are_held_back(capfd):
    from slicecap.abrdf_exr import _openexr_damage_lines_held

    with _openexr_damage_lines_held():
        os.write(2, b"x.exr: (EXR_ERR_BAD_CHUNK_LEADER) Invalid chunk size\n")
        os.write(2, b"something else on stderr\n")
        print("Warning: Exception raised reading pixel data for part 0 - ...")
        print("a script's own line")
    assert capfd.readouterr() == ("a script's own line\n", "something else on stderr\n")


def test_without_a_temporary_file_a_table_still_reads(tmp_path, monkeypatch):
    # The hold's temporary file failed every read, with an error naming the temporary path, and
    # left sys.stdout redirected.
    write_abrdf_exr(tmp_path / "whole.exr", ramp_table())
    stdout = sys.stdout
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "no-such-folder"))
    np.testing.assert_array_equal(read_abrdf_exr(tmp_path / "whole.exr").values, ramp_table())
    assert sys.stdout is stdout


def test_reading_from_many_threads_leaves_stdout_and_stderr_as_they_were(tmp_path, capfd):
    # The holds redirect process-wide state; overlapping ones left stdout a StringIO and
    # descriptor 2 on a deleted temporary file for good.
    write_abrdf_exr(tmp_path / "whole.exr", ramp_table())
    whole = (tmp_path / "whole.exr").read_bytes()
    (tmp_path / "cut.exr").write_bytes(whole[: len(whole) // 2])
    stdout, descriptor_2 = sys.stdout, os.fstat(2)

    def read_many(k):
        for i in range(25):
            try:
                read_abrdf_exr(tmp_path / ("cut.exr" if (i + k) % 2 else "whole.exr"))
            except SlicecapFileError:
                pass

    threads = [threading.Thread(target=read_many, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sys.stdout is stdout
    assert (os.fstat(2).st_ino, os.fstat(2).st_dev) == (descriptor_2.st_ino, descriptor_2.st_dev)
    assert capfd.readouterr() == ("", "")


def test_half_float_channels_are_read_as_float32(tmp_path):
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    header.update(GOOD_ATTRIBUTES)
    half = ramp_table().astype(np.float16)
    with OpenEXR.File(header, {c: half[..., i].copy() for i, c in enumerate("RGB")}) as file:
        file.write(str(tmp_path / "half.exr"))
    back = read_abrdf_exr(tmp_path / "half.exr")
    assert back.values.dtype == np.float32
    np.testing.assert_array_equal(back.values, half.astype(np.float32))


def test_rejects_tables_of_another_shape():
    with pytest.raises(ValueError, match=r"\(81, 81, 3\)"):
        Abrdf(np.zeros((81, 80, 3)))


def test_reads_what_the_cpp_side_writes_and_the_reverse(tmp_path, slicecap_cli):
    subprocess.run(
        [slicecap_cli, "generate", "satin-blue-45", "-o", tmp_path / "cpp.exr"],
        check=True,
        capture_output=True,
    )
    subprocess.run(
        [slicecap_cli, "generate", "satin-blue-45", "-o", tmp_path / "cpp.f32"],
        check=True,
        capture_output=True,
    )
    table = read_abrdf_exr(tmp_path / "cpp.exr")
    f32 = np.fromfile(tmp_path / "cpp.f32", dtype="<f4").reshape(81, 81, 3)
    np.testing.assert_array_equal(table.values, f32)
    assert table.attributes["material"] == "satin-blue-45"
    assert table.attributes["method"] == "analytic"

    write_abrdf_exr(tmp_path / "py.exr", table.values * 0.5, {"method": "analytic"})
    compared = subprocess.run(
        [slicecap_cli, "compare", tmp_path / "cpp.exr", tmp_path / "py.exr", "--json"],
        check=True,
        capture_output=True,
        text=True,
    )
    # The C++ reader sees exactly half the reference in the Python-written file.
    assert json.loads(compared.stdout)["relative_rmse"] == pytest.approx(0.5, abs=1e-6)
    rejected = subprocess.run(
        [slicecap_cli, "compare", tmp_path / "cpp.exr", tmp_path / "none.exr"],
        capture_output=True,
        text=True,
    )
    assert rejected.returncode == 1
