"""Reading the SVBRDF maps `slicecap fit BTF_DIR -o MAPS_DIR` writes (docs/material-fit.md,
"Texture mode") back into the fit model's parameters per texel, undoing the glTF packing of
lib/material_export texture_maps.cpp. The viewer's plane (docs/material-viewer.md) decodes the
same bytes the same way in its shader; this is the numpy side of that decoding.
"""

import json
import math
import os
from dataclasses import dataclass

import numpy as np

from slicecap.abrdf_exr import SlicecapFileError
from slicecap.fitted_material import FittedMaterial
from slicecap.paths import StrPath
from slicecap.png import read_png_channels

MANIFEST = "maps.json"
# file -> channels the C++ writes (libpng colour type by channel count).
MAP_FILES = {
    "base_color.png": 3,
    "metallic_roughness.png": 3,
    "anisotropy.png": 3,
    "specular.png": 4,
    "mask.png": 1,
}
# The fitted shading normals (docs/material-fit.md "The normal map"): RGB = (n' + 1) / 2, 8-bit
# linear, x along the tangent (+x), y along the bitangent (+y), z out of the surface. Read apart
# from MAP_FILES: maps of a `slicecap fit` from before the normal map have none (read_maps).
NORMAL_MAP = "normal.png"
# The byte the C++ writes for a component 0 (lround(255 x 0.5) = 128) and the writer's scale:
# the viewer decodes x = (byte - 128) / 127.5, so 128 is exactly 0 and a flat map is exactly
# (0, 0, 1). That is the lower edge of the writer's rounding interval for each byte (exact for
# the fit's flat normals, half a step = 0.0039 = 0.22 deg low for a tilted component).
NORMAL_ZERO_BYTE = 128
NORMAL_BYTE_SCALE = 127.5
# maps.json's key that a `slicecap fit` writing normal.png adds (lib/cli texture_fit_command).
_TILT_KEY = "texels_tilt_fitted"
# The fit's smallest alpha (docs/material-fit.md, bounds): a roughness byte of 0 gives alpha 0,
# where GGX's D divides by zero.
MIN_ALPHA = 0.002


@dataclass(frozen=True)
class SvbrdfMaps:
    """The maps' bytes (row 0 = the texture's row 0 = the plane's top edge) and the shared IOR."""

    directory: str
    resolution: int
    ior: float
    images: dict[str, np.ndarray]  # file name -> (n, n, channels) uint8
    png_bytes: dict[str, bytes]  # file name -> the file as written, for data: URIs
    # None when normal.png was read; else why every texel is shown untilted (maps of a fit older
    # than the normal map have no normal.png: images then holds a flat one).
    normal_note: str | None = None

    @property
    def fitted(self) -> np.ndarray:
        """(n, n) bool: the texels mask.png says were fitted."""
        return self.images["mask.png"][..., 0] >= 128

    @property
    def ior_f0(self) -> float:
        """F0 of the shared IOR: what a specular colour of 1 and specularFactor 1 reflect."""
        return ((self.ior - 1.0) / (self.ior + 1.0)) ** 2


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    """Linear values of sRGB-encoded ones in [0, 1] (the exact piecewise curve)."""
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)


def decode_parameters(maps: SvbrdfMaps) -> dict[str, np.ndarray]:
    """Per texel the fit model's parameters, as the page's shader decodes them (loadTexel):
    f90 = specular A; f0 = F0(ior) x specular RGB (sRGB) x f90; diffuse = base colour (sRGB) x
    (1 - f0); alpha_b = roughness^2; alpha_t = mix(alpha_b, 1, strength^2); the tangent at
    atan2 of anisotropy RG mapped to [-1, 1]. Arrays (n, n[, 3]) of float64."""
    def unit(name: str) -> np.ndarray:
        return maps.images[name].astype(np.float64) / 255.0

    specular = unit("specular.png")
    f90 = specular[..., 3]
    f0 = maps.ior_f0 * srgb_decode(specular[..., :3]) * f90[..., None]
    diffuse = srgb_decode(unit("base_color.png")) * (1.0 - f0)
    roughness = unit("metallic_roughness.png")[..., 1]
    alpha_b = np.maximum(roughness * roughness, MIN_ALPHA)
    anisotropy = unit("anisotropy.png")
    strength = anisotropy[..., 2]
    alpha_t = np.maximum(alpha_b + (1.0 - alpha_b) * strength * strength, MIN_ALPHA)
    tangent_deg = np.degrees(np.arctan2(2.0 * anisotropy[..., 1] - 1.0,
                                        2.0 * anisotropy[..., 0] - 1.0))
    return {"diffuse_albedo": diffuse, "specular_f0": f0, "specular_f90": f90,
            "alpha_tangent": alpha_t, "alpha_bitangent": alpha_b, "tangent_deg": tangent_deg}


def shading_normals(maps: SvbrdfMaps) -> np.ndarray:
    """(n, n, 3) float64 unit shading normals in each texel's frame (x = tangent +x, y =
    bitangent +y, z = the surface normal), as the page's shader decodes normal.png (loadTexel):
    x, y = (R, G byte - 128) / 127.5, z = sqrt(1 - x^2 - y^2), the fit's own parameterisation
    (lib/fit tilted_lobe.hpp); B is not read (it holds that z to 8 bits). Bytes 128, 128 give
    (0, 0, 1) exactly; x^2 + y^2 above 1 (no fit writes it) is clipped to the horizon."""
    rg = maps.images[NORMAL_MAP][..., :2].astype(np.float64)
    x = (rg[..., 0] - NORMAL_ZERO_BYTE) / NORMAL_BYTE_SCALE
    y = (rg[..., 1] - NORMAL_ZERO_BYTE) / NORMAL_BYTE_SCALE
    z = np.sqrt(np.maximum(1.0 - x * x - y * y, 0.0))
    normal = np.stack([x, y, z], axis=-1)
    return normal / np.linalg.norm(normal, axis=-1, keepdims=True)


def tilted(maps: SvbrdfMaps) -> np.ndarray:
    """(n, n) bool: texels whose normal.png R, G are not both 128 (the shader's test too): only
    these take the tilted frame, so a flat map renders exactly as no map."""
    rg = maps.images[NORMAL_MAP][..., :2]
    return np.any(rg != NORMAL_ZERO_BYTE, axis=-1)


def texel_materials(maps: SvbrdfMaps) -> list[list[FittedMaterial | None]]:
    """[row][column] the texel's material (slicecap.fitted_material's model, GGX only), None
    where the mask says it was not fitted."""
    p = decode_parameters(maps)
    fitted = maps.fitted
    n = maps.resolution

    def rgb(values: np.ndarray) -> tuple[float, float, float]:
        return (float(values[0]), float(values[1]), float(values[2]))

    def material(y: int, x: int) -> FittedMaterial:
        return FittedMaterial(
            "ggx", rgb(p["diffuse_albedo"][y, x]), rgb(p["specular_f0"][y, x]),
            float(p["specular_f90"][y, x]),
            float(p["alpha_tangent"][y, x]), float(p["alpha_bitangent"][y, x]),
            float(p["tangent_deg"][y, x]),
        )

    return [[material(y, x) if fitted[y, x] else None for x in range(n)] for y in range(n)]


def _manifest(directory: str) -> tuple[int, float, bool]:
    path = os.path.join(directory, MANIFEST)
    try:
        with open(path, encoding="utf-8") as file:
            document = json.load(file)
    except FileNotFoundError:
        raise SlicecapFileError(f"{path}: missing: {directory} is not a MAPS_DIR of "
                                "`slicecap fit BTF_DIR -o MAPS_DIR`") from None
    except (OSError, ValueError) as e:
        raise SlicecapFileError(f"{path}: not JSON ({e})") from None
    if not isinstance(document, dict) or document.get("format") != "slicecap-svbrdf":
        raise SlicecapFileError(f'{path}: not slicecap SVBRDF maps ("format" is not '
                                '"slicecap-svbrdf")')
    resolution, ior = document.get("resolution"), document.get("ior")
    if not isinstance(resolution, int) or isinstance(resolution, bool) or resolution < 1:
        raise SlicecapFileError(f'{path}: "resolution" must be a positive whole number')
    if not isinstance(ior, (int, float)) or not math.isfinite(ior) or ior < 1.0:
        raise SlicecapFileError(f'{path}: "ior" must be a number >= 1')
    return resolution, float(ior), _TILT_KEY in document


def _read_png(path: str, resolution: int, channels: int) -> tuple[bytes, np.ndarray]:
    try:
        with open(path, "rb") as handle:
            raw = handle.read()
        image = read_png_channels(path)
    except FileNotFoundError:
        raise  # the caller says why the file is needed
    except OSError as e:
        raise SlicecapFileError(f"{path}: cannot read ({e.strerror})") from None
    except ValueError as e:
        raise SlicecapFileError(str(e)) from None
    if image.shape[:2] != (resolution, resolution):
        raise SlicecapFileError(
            f"{path}: {image.shape[1]} x {image.shape[0]} texels, maps.json says "
            f"{resolution} x {resolution}")
    if image.shape[2] != channels:
        raise SlicecapFileError(f"{path}: {image.shape[2]} channels, expected {channels}")
    return raw, image


def read_maps(directory: StrPath) -> SvbrdfMaps:
    """The maps of MAPS_DIR. Raises SlicecapFileError naming the file: maps.json missing or not
    slicecap-svbrdf, a map missing, not a PNG, truncated, of another size than maps.json's
    resolution or with other channels than the C++ writes. normal.png is needed when maps.json
    says the fit wrote one (texels_tilt_fitted); otherwise its absence gives flat normals and
    SvbrdfMaps.normal_note."""
    name = os.fspath(directory)
    if not os.path.isdir(name):
        raise SlicecapFileError(f"{name}: not a directory (a MAPS_DIR of `slicecap fit`)")
    resolution, ior, has_normal_map = _manifest(name)
    images, raw = {}, {}
    for file, channels in MAP_FILES.items():
        path = os.path.join(name, file)
        try:
            raw[file], images[file] = _read_png(path, resolution, channels)
        except FileNotFoundError:
            raise SlicecapFileError(f"{path}: missing (every map of docs/material-fit.md is "
                                    "needed)") from None
    path = os.path.join(name, NORMAL_MAP)
    note = None
    try:
        raw[NORMAL_MAP], images[NORMAL_MAP] = _read_png(path, resolution, 3)
    except FileNotFoundError:
        if has_normal_map:  # written by a fit that writes normal.png: the folder lost it
            raise SlicecapFileError(
                f"{path}: missing (maps.json counts {_TILT_KEY}: the fit wrote a normal map; "
                "without it every tilt would be shown flat)") from None
        # Maps of a fit from before the normal map: its texels were fitted untilted, so flat
        # is what that fit meant.
        images[NORMAL_MAP] = np.zeros((resolution, resolution, 3), np.uint8) + np.array(
            [NORMAL_ZERO_BYTE, NORMAL_ZERO_BYTE, 255], np.uint8)
        note = (f"{path}: missing (maps of a slicecap fit from before the normal map): "
                "every texel shown untilted")
    return SvbrdfMaps(name, resolution, ior, images, raw, note)
