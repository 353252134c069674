"""Reading the BTF directory `slicecap btf` writes (docs/btf-format.md): every texel of the window
with its own 81 x 81 apparent BRDF, as 6561 half-float EXR images in the UTIA naming, the average
ABRDF and a JSON manifest. The checks and messages follow the C++ reader (btf::readBtfDirectory).
"""

import json
import math
import os
import pathlib
from dataclasses import dataclass, field

import numpy as np

from slicecap.abrdf import Abrdf
from slicecap.abrdf_exr import SlicecapFileError, read_abrdf_exr, read_exr
from slicecap.grid import direction_of_index, is_whole_number
from slicecap.paths import StrPath

MANIFEST = "btf.json"
DEFAULT_AVERAGE = "average.exr"
DIRECTIONS = 81
CHANNELS = ("R", "G", "B")


def _three_digits(degrees: float) -> str:
    # As the C++ writer: std::lround (halves away from zero; every Bonn angle is >= 0).
    return f"{int(math.floor(degrees + 0.5)) % 1000:03d}"


def image_path(light: int, view: int) -> str:
    """The image of (light index, view index) relative to the BTF directory:
    "tvTTT_pvPPP/tlTTT_plPPP_tvTTT_pvPPP.exr" (whole degrees of the Bonn directions)."""
    theta_l, phi_l = direction_of_index(light)
    theta_v, phi_v = direction_of_index(view)
    view_name = f"tv{_three_digits(theta_v)}_pv{_three_digits(phi_v)}"
    return f"{view_name}/tl{_three_digits(theta_l)}_pl{_three_digits(phi_l)}_{view_name}.exr"


@dataclass
class Btf:
    """A BTF: `images[light, view, row, column, channel]` (float16, as stored: N = 128 takes 645
    MB), row 0 at the window's top (largest y) and column 0 at its left edge (smallest x); the
    manifest; the average ABRDF."""

    images: np.ndarray
    manifest: dict = field(default_factory=dict)
    average: Abrdf | None = None

    @property
    def resolution(self) -> int:
        return int(self.images.shape[2])

    @property
    def window_mm(self) -> tuple[float, float, float, float]:
        """(x_min, y_min, x_max, y_max) of the window in the target frame, mm."""
        x_min, y_min, x_max, y_max = (float(v) for v in self.manifest["window_mm"])
        return x_min, y_min, x_max, y_max

    def texel(self, column: int, row: int) -> Abrdf:
        """The 81 x 81 apparent BRDF of one texel (float32): column 0..N-1 from the left, row
        0..N-1 from the top. Raises IndexError outside (numpy would take -1 as the last one),
        TypeError for what is not a whole number."""
        for name, value in (("column", column), ("row", row)):
            if not is_whole_number(value):
                raise TypeError(f"texel {name} must be a whole number, got {value!r}")
            if not 0 <= value < self.resolution:
                raise IndexError(
                    f"texel {name} {value} is outside 0..{self.resolution - 1} "
                    f"(the BTF is {self.resolution} x {self.resolution})"
                )
        return Abrdf(self.images[:, :, row, column, :].astype(np.float32))


def _error(path: StrPath, what: str) -> SlicecapFileError:
    return SlicecapFileError(f"{os.fspath(path)}: {what}")


def _read_image(path: pathlib.Path, resolution: int) -> np.ndarray:
    header, channels = read_exr(path, "a BTF image")
    low, high = header["dataWindow"]
    width, height = int(high[0] - low[0] + 1), int(high[1] - low[1] + 1)
    if (width, height) != (resolution, resolution):
        raise _error(
            path, f"{width} x {height} texels, the manifest says {resolution} x {resolution}"
        )
    for name in CHANNELS:
        if name not in channels:
            raise _error(path, f"no channel {name} (a BTF image has R, G, B)")
    try:
        with np.errstate(over="ignore", invalid="ignore"):  # reported below, naming the texel
            image = np.stack(
                [np.asarray(channels[name].pixels, dtype=np.float16) for name in CHANNELS],
                axis=-1,
            )
    except Exception as e:  # e.g. pixels of a type numpy does not convert
        raise _error(path, f"cannot read EXR: {e}") from e
    bad = np.argwhere(~np.isfinite(image))
    if len(bad):
        row, column, channel = bad[0]
        raise _error(
            path,
            f"non-finite value (as a half float) at column {column}, row {row}, "
            f"channel {CHANNELS[channel]}",
        )
    return image


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _check_manifest(path: pathlib.Path, manifest: object) -> None:
    """The manifest's fields this package relies on, each refused naming btf.json."""
    if not isinstance(manifest, dict):
        raise _error(path, f"not a JSON object but {type(manifest).__name__}")
    if manifest.get("format") != "slicecap-btf":
        raise _error(path, "field 'format' is not \"slicecap-btf\"")
    resolution = manifest.get("resolution")
    if type(resolution) is not int or not 1 <= resolution <= 1024:
        raise _error(path, "field 'resolution' is not a whole number in 1..1024")
    window = manifest.get("window_mm")
    if (
        not isinstance(window, list)
        or len(window) != 4
        or not all(_is_number(v) for v in window)
        or not (window[0] < window[2] and window[1] < window[3])
    ):
        raise _error(
            path, "field 'window_mm' is not [x_min, y_min, x_max, y_max] (mm, min < max)"
        )
    average = manifest.get("average", DEFAULT_AVERAGE)
    if not isinstance(average, str) or not average:
        raise _error(path, "field 'average' is not a file name")


def read_btf(directory: StrPath) -> Btf:
    """Reads a BTF directory: btf.json (format "slicecap-btf", its resolution and window), all
    6561 images (each N x N, R G B, finite half floats) and average.exr. Raises
    SlicecapFileError naming the file that is missing or wrong."""
    directory = pathlib.Path(directory)
    manifest_path = directory / MANIFEST
    try:
        manifest = json.loads(manifest_path.read_bytes())
    except OSError as e:
        raise _error(manifest_path, f"cannot open (not a BTF directory?): {e.strerror}") from e
    except ValueError as e:  # not JSON, or not text at all (UnicodeDecodeError)
        raise _error(manifest_path, f"not JSON: {e}") from e
    except RecursionError as e:  # the C++ readers refuse nesting past 64 levels; btf.json nests 2
        raise _error(manifest_path, "not JSON: nested too deep") from e
    _check_manifest(manifest_path, manifest)
    resolution = manifest["resolution"]
    # The first image before the 6561 x N x N array: a resolution the images do not have is
    # named as such, not as numpy's failure to allocate tens of GiB.
    first = _read_image(directory / image_path(0, 0), resolution)
    images = np.empty((DIRECTIONS, DIRECTIONS, resolution, resolution, 3), dtype=np.float16)
    images[0, 0] = first
    for light in range(DIRECTIONS):
        for view in range(1 if light == 0 else 0, DIRECTIONS):
            images[light, view] = _read_image(directory / image_path(light, view), resolution)
    average = read_abrdf_exr(directory / manifest.get("average", DEFAULT_AVERAGE))
    return Btf(images, manifest, average)
