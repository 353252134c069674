"""ABRDF EXR reading and writing, with the C++ reader's checks and messages (lib/io/abrdf_exr).

One 81 x 81 image, channels R, G, B as float32 (ZIP), row = light index, column = view index,
BRDF in 1/sr; string attributes `slicecap:layout` = "bonn81" and `slicecap:quantity` = "brdf".
"""

import contextlib
import io
import os
import re
import sys
import tempfile
import threading
from collections.abc import Iterator
from typing import IO, TextIO

import numpy as np
import OpenEXR
from numpy.typing import ArrayLike

from slicecap._version import __version__
from slicecap.abrdf import Abrdf
from slicecap.paths import StrPath, write_replacing

PREFIX = "slicecap:"
CHANNELS = ("R", "G", "B")
SIZE = 81
ABRDF_LAYOUT = "bonn81"
VERSION = f"{__version__} (python)"
EXR_MAGIC = b"\x76\x2f\x31\x01"


class SlicecapFileError(RuntimeError):
    """A file that cannot be read or written as asked; the message starts with the file's path
    (the Python counterpart of the C++ slicecap::io::IoError)."""


def _error(path: StrPath, what: str) -> SlicecapFileError:
    return SlicecapFileError(f"{os.fspath(path)}: {what}")


def slicecap_attributes(header: dict) -> dict[str, str]:
    """The `slicecap:*` string attributes of an EXR header, without the prefix."""
    return {
        name[len(PREFIX) :]: value
        for name, value in header.items()
        if name.startswith(PREFIX) and isinstance(value, str)
    }


def first_invalid_value(values: np.ndarray) -> str | None:
    """The first value an (81, 81, 3) BRDF table may not hold, with its place: "non-finite value
    at light 3, view 40, channel G" or "negative value -0.25 at light 3, view 40, channel G (a BRDF
    is never negative)"; None when every value is finite and not negative (-0 is zero). The C++
    io::firstInvalidValue, word for word."""
    values = np.asarray(values)
    bad = np.argwhere(~np.isfinite(values) | (values < 0))
    if not len(bad):
        return None
    light, view, channel = bad[0]
    where = f"at light {light}, view {view}, channel {CHANNELS[channel]}"
    value = values[light, view, channel]
    if not np.isfinite(value):
        return f"non-finite value {where}"
    return f"negative value {float(value):g} {where} (a BRDF is never negative)"


def _refuse_unopenable(path: StrPath, expected: str) -> str:
    """The path as a string, once it names a readable file that starts as an EXR does. OpenEXR's
    bindings say only "Unable to open 'PATH' for read" for a missing file, a directory, an empty
    or a text file alike (the reason goes to stderr); this says which."""
    name = os.fspath(path)
    if os.path.isdir(name):
        raise _error(path, f"is a directory, not {expected}")
    try:
        with open(name, "rb") as file:
            magic = file.read(len(EXR_MAGIC))
    except OSError as e:
        raise _error(path, f"cannot read EXR: {e.strerror}") from e
    if magic != EXR_MAGIC:
        what = "an empty file" if not magic else "no EXR magic number"
        raise _error(path, f"cannot read EXR: not an OpenEXR file ({what})")
    return name


# OpenEXR's own lines about a damaged file: its C core's "PATH: (EXR_ERR_...) ..." on descriptor 2
# and the bindings' "Warning: Exception raised reading pixel data ..." on sys.stdout.
_OPENEXR_DAMAGE_LINE = re.compile(r"\(EXR_ERR_[A-Z_]+\)|^Warning: Exception raised reading ")
# The holds redirect process-wide state: two at once would each take the other's for the original
# and leave stdout and descriptor 2 redirected for good (8 threads reading at once did).
_HOLD_LOCK = threading.RLock()


def _pass_on(text: str, stream: TextIO | None) -> None:
    if stream is None:  # pythonw
        return
    for line in text.splitlines():
        if not _OPENEXR_DAMAGE_LINE.search(line):
            stream.write(line + "\n")


@contextlib.contextmanager
def _openexr_damage_lines_held() -> Iterator[None]:
    """While OpenEXR reads a file: what it prints is held and, at exit, passed on where it was
    going (descriptor 2 to sys.stderr, sys.stdout to sys.stdout), except OpenEXR's own lines about
    a damaged file (a line per chunk it cannot place, then a warning on sys.stdout, where it would
    land in a script's own output): the error raised says it once, naming the file. One hold at a
    time; what other threads print meanwhile is held and passed on with it. Without a descriptor
    2 (pythonw) or a temporary file, descriptor 2 is not held."""
    with _HOLD_LOCK:
        python_side = io.StringIO()
        sink: IO[bytes] | None = None
        saved: int | None = None
        try:
            sink = tempfile.TemporaryFile()
            if sys.stderr is not None:
                sys.stderr.flush()
            saved = os.dup(2)
        except (OSError, ValueError):
            if sink is not None:
                sink.close()
            sink = None
        try:
            if saved is not None and sink is not None:  # saved is only set once sink is
                os.dup2(sink.fileno(), 2)
            with contextlib.redirect_stdout(python_side):
                yield
        finally:
            held = ""
            if saved is not None and sink is not None:
                os.dup2(saved, 2)
                os.close(saved)
                sink.seek(0)
                held = sink.read().decode(errors="replace")
            if sink is not None:
                sink.close()
            _pass_on(held, sys.stderr)
            _pass_on(python_side.getvalue(), sys.stdout)


def read_exr(path: StrPath, expected: str) -> tuple[dict, dict]:
    """(header, channels) of an EXR's first part, pixels read, channels separate. Raises
    SlicecapFileError naming the file and what is wrong: missing, a directory, not an EXR, a
    damaged header, truncated or corrupt pixel data (where the bindings print a warning and
    leave a file of no parts, which then says only "Invalid part index '0': file has 0 parts").
    OpenEXR's own lines about a damaged file are not printed (the error says it)."""
    name = _refuse_unopenable(path, expected)
    failure: Exception | None = None
    with _openexr_damage_lines_held():
        try:
            with OpenEXR.File(name, separate_channels=True) as file:
                if file.parts:
                    return dict(file.header()), dict(file.channels())
        except Exception as e:  # the bindings raise several types
            failure = e
    try:
        with _openexr_damage_lines_held():
            with OpenEXR.File(name, header_only=True) as file:
                file.header()
    except Exception as e:
        raise _error(path, "cannot read EXR: its header is truncated or corrupt") from e
    raise _error(path, "cannot read EXR: its pixel data is truncated or corrupt") from failure


def read_exr_header(path: StrPath) -> dict:
    """The header of any EXR file (no pixels); raises SlicecapFileError naming the file."""
    name = _refuse_unopenable(path, "an EXR file")
    try:
        with _openexr_damage_lines_held(), OpenEXR.File(name, header_only=True) as file:
            return dict(file.header())
    except Exception as e:  # the bindings raise several types for missing and corrupt files
        raise _error(path, "cannot read EXR: its header is truncated or corrupt") from e


def _require(path: StrPath, found: dict[str, str], key: str, expected: str) -> None:
    if key not in found:
        raise _error(
            path,
            f'missing header attribute {PREFIX}{key} (expected "{expected}"); '
            "is this a slicecap ABRDF?",
        )
    if found[key] != expected:
        raise _error(
            path, f'header attribute {PREFIX}{key} is "{found[key]}", expected "{expected}"'
        )


def read_abrdf_exr(path: StrPath) -> Abrdf:
    """Reads an ABRDF EXR; checks the 81 x 81 size, the R, G, B channels, `slicecap:layout` =
    "bonn81", `slicecap:quantity` = "brdf" and finite, non-negative values. Raises
    SlicecapFileError whose message names the file and what is wrong (the same messages as the
    C++ reader)."""
    header, channels = read_exr(path, "an ABRDF EXR")
    try:
        low, high = header["dataWindow"]
        width = int(high[0] - low[0] + 1)
        height = int(high[1] - low[1] + 1)
        if width != SIZE or height != SIZE:
            raise _error(
                path,
                "ABRDF EXR must be 81 x 81 (light rows x view columns), "
                f"got {height} x {width}",
            )
        for name in CHANNELS:
            if name not in channels:
                raise _error(path, f"ABRDF EXR has no channel {name} (needs R, G, B)")
        found = slicecap_attributes(header)
        _require(path, found, "layout", ABRDF_LAYOUT)
        _require(path, found, "quantity", "brdf")
        values = np.stack(
            [np.asarray(channels[name].pixels, dtype=np.float32) for name in CHANNELS],
            axis=-1,
        )
    except SlicecapFileError:
        raise
    except Exception as e:  # e.g. pixels of a type numpy does not convert
        raise _error(path, f"cannot read EXR: {e}") from e
    problem = first_invalid_value(values)
    if problem:
        raise _error(path, problem)
    return Abrdf(values, found)


def write_abrdf_exr(
    path: StrPath, table: Abrdf | ArrayLike, attributes: dict[str, str] | None = None
) -> None:
    """Writes an (81, 81, 3) table or an Abrdf (ZIP compressed, float32). The writer always sets
    layout = "bonn81", quantity = "brdf" and (unless given) version. Raises SlicecapFileError
    naming the file on failure or for a table with a non-finite or negative value (the reader
    refuses such a file, as the C++ writer does), ValueError for a table of another shape."""
    abrdf = table if isinstance(table, Abrdf) else Abrdf(np.asarray(table))
    problem = first_invalid_value(abrdf.values)
    if problem:
        raise _error(path, f"not written: a {problem}")
    merged = dict(abrdf.attributes)
    merged.update(attributes or {})
    merged["layout"] = ABRDF_LAYOUT
    merged["quantity"] = "brdf"
    merged.setdefault("version", VERSION)
    header = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
    }
    header.update({PREFIX + key: str(value) for key, value in merged.items()})
    channels = {name: np.ascontiguousarray(abrdf.values[..., c]) for c, name in enumerate(CHANNELS)}
    try:
        with OpenEXR.File(header, channels) as file:
            write_replacing(path, lambda temporary: file.write(temporary))
    except Exception as e:
        raise _error(path, f"cannot write EXR: {e}") from e
