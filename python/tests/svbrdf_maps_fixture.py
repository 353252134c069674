"""Small SVBRDF maps for the viewer's tests, written as `slicecap fit BTF_DIR -o MAPS_DIR` packs
them (lib/material_export texture_maps.cpp and gltf_material.cpp: the glTF factors per texel),
from known fit-model materials, with texels the mask marks as not fitted."""

import json
import math
import struct
import zlib

import numpy as np

from slicecap.fitted_material import FittedMaterial


def png_bytes(image: np.ndarray) -> bytes:
    """An 8-bit PNG of an (H, W, C) uint8 image, C = 1, 3 or 4 (libpng's colour types)."""
    height, width, channels = image.shape
    colour = {1: 0, 3: 2, 4: 6}[channels]

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data)))

    rows = np.concatenate([np.zeros((height, 1), np.uint8), image.reshape(height, -1)], axis=1)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8,
                                                             colour, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows.tobytes())) + chunk(b"IEND", b""))


def _srgb8(x: float) -> int:
    x = min(max(x, 0.0), 1.0)
    return round(255 * (12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055))


def _linear8(x: float) -> int:
    return round(255 * min(max(x, 0.0), 1.0))


def f0_of_ior(ior: float) -> float:
    return ((ior - 1) / (ior + 1)) ** 2


def write_maps(directory, materials: list[list[FittedMaterial | None]]) -> None:
    """MAPS_DIR for an n x n grid of materials (None = not fitted): the C++'s packing, the
    shared IOR from the brightest F0 / F90 ratio."""
    n = len(materials)
    base = np.zeros((n, n, 3), np.uint8)
    rough = np.zeros((n, n, 3), np.uint8)
    rough[..., 1] = 255
    aniso = np.zeros((n, n, 3), np.uint8)
    spec = np.zeros((n, n, 4), np.uint8)
    mask = np.zeros((n, n, 1), np.uint8)
    ratio = max(max(m.specular_f0) / max(m.specular_f90, max(m.specular_f0))
                for row in materials for m in row if m is not None)
    ior_f0 = min(ratio, 0.9)
    ior = (1 + math.sqrt(ior_f0)) / (1 - math.sqrt(ior_f0))
    for y, row in enumerate(materials):
        for x, m in enumerate(row):
            if m is None:
                continue
            mask[y, x] = 255
            f90 = max(m.specular_f90, max(m.specular_f0))
            spec[y, x, 3] = _linear8(f90)
            for c in range(3):
                spec[y, x, c] = _srgb8(m.specular_f0[c] / f90 / ior_f0)
                base[y, x, c] = _srgb8(m.diffuse_albedo[c] / (1 - m.specular_f0[c]))
            rough[y, x, 1] = _linear8(math.sqrt(m.alpha_bitangent))
            strength = math.sqrt((m.alpha_tangent - m.alpha_bitangent) / (1 - m.alpha_bitangent))
            angle = math.radians(m.tangent_deg)
            aniso[y, x] = (_linear8(0.5 + 0.5 * math.cos(angle)),
                           _linear8(0.5 + 0.5 * math.sin(angle)), _linear8(strength))
    directory.mkdir(parents=True, exist_ok=True)
    normal = np.zeros((n, n, 3), np.uint8) + np.array([128, 128, 255], np.uint8)
    for name, image in (("base_color.png", base), ("metallic_roughness.png", rough),
                        ("anisotropy.png", aniso), ("specular.png", spec), ("normal.png", normal),
                        ("mask.png", mask)):
        (directory / name).write_bytes(png_bytes(image))
    (directory / "maps.json").write_text(json.dumps({
        "format": "slicecap-svbrdf", "format_version": 1, "model": "ggx", "resolution": n,
        "ior": ior, "texels_fitted": int(np.count_nonzero(mask))}))


def brushed_tiles(n: int) -> list[list[FittedMaterial | None]]:
    """An n x n texture: a brushed metal whose brushing turns across the columns (0..150 deg)
    and whose colour changes down the rows, with the texel (1, n - 2) not fitted."""
    rows: list[list[FittedMaterial | None]] = []
    for y in range(n):
        row: list[FittedMaterial | None] = []
        for x in range(n):
            tint = y / max(n - 1, 1)
            row.append(FittedMaterial(
                "ggx", (0.05 + 0.25 * tint, 0.08, 0.3 - 0.2 * tint),
                (0.5, 0.45 + 0.2 * tint, 0.4), 0.9, 0.45, 0.08, 150.0 * x / max(n - 1, 1)))
        rows.append(row)
    rows[n - 2][1] = None
    return rows
