"""A minimal PNG writer (8-bit RGB), so the renderer's picture needs no imaging library."""

import os
import struct
import zlib

import numpy as np

from slicecap.paths import write_replacing


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def encode_png(image: np.ndarray) -> bytes:
    """The PNG file's bytes of an (H, W, 3) uint8 image (e.g. for a data: URI); ValueError for
    another shape."""
    image = np.ascontiguousarray(image, dtype=np.uint8)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"write_png: expected an (H, W, 3) image, got {image.shape}")
    height, width = image.shape[:2]
    rows = np.concatenate([np.zeros((height, 1), np.uint8), image.reshape(height, -1)], axis=1)
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + _chunk(b"IHDR", header)
        + _chunk(b"sRGB", b"\x00")
        + _chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
        + _chunk(b"IEND", b"")
    )


def write_png(path, image: np.ndarray) -> None:
    """Writes an (H, W, 3) uint8 image through a temporary renamed onto PATH (paths.write_replacing);
    raises OSError (naming the file) when it cannot."""
    data = encode_png(image)

    def write(target):
        with open(target, "wb") as file:
            file.write(data)

    try:
        write_replacing(path, write)
    except OSError as e:
        # The error of a write names no file, that of the temporary's open the temporary.
        raise OSError(e.errno, e.strerror, os.fspath(path)) from e


def read_png_size(path) -> tuple[int, int]:
    """(width, height) from a PNG's header (for checks)."""
    with open(os.fspath(path), "rb") as file:
        head = file.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{os.fspath(path)}: not a PNG file")
    return struct.unpack(">II", head[16:24])
