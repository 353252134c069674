"""A minimal PNG writer (8-bit RGB), so the renderer's picture needs no imaging library."""

import os
import struct
import zlib

import numpy as np

from slicecap.paths import StrPath, write_replacing


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def encode_png(image: np.ndarray) -> bytes:
    """The PNG file's bytes of an (H, W, 3) uint8 image (e.g. for a data: URI); ValueError for
    another shape."""
    image = np.ascontiguousarray(image, dtype=np.uint8)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"encode_png: expected an (H, W, 3) image, got {image.shape}")
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


def write_png(path: StrPath, image: np.ndarray) -> None:
    """Writes an (H, W, 3) uint8 image through a temporary renamed onto PATH
    (paths.write_replacing); raises OSError (naming the file) when it cannot."""
    data = encode_png(image)

    def write(target: str) -> None:
        with open(target, "wb") as file:
            file.write(data)

    try:
        write_replacing(path, write)
    except OSError as e:
        # The error of a write names no file, that of the temporary's open the temporary.
        raise OSError(e.errno, e.strerror, os.fspath(path)) from e


def read_png_size(path: StrPath) -> tuple[int, int]:
    """(width, height) from a PNG's header (for checks)."""
    with open(os.fspath(path), "rb") as file:
        head = file.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{os.fspath(path)}: not a PNG file")
    return struct.unpack(">II", head[16:24])


def _unfilter(kind: int, row: np.ndarray, previous: np.ndarray, stride: int) -> np.ndarray:
    """One scanline's bytes after PNG filter `kind` (0 none, 1 sub, 2 up, 3 average, 4 Paeth)."""
    if kind == 0:
        return row
    if kind == 2:
        return (row + previous).astype(np.uint8)
    out = row.astype(np.int32)
    above = previous.astype(np.int32)
    for i in range(len(out)):
        left = out[i - stride] if i >= stride else 0
        upper_left = above[i - stride] if i >= stride else 0
        if kind == 1:
            out[i] = (out[i] + left) & 255
        elif kind == 3:
            out[i] = (out[i] + (left + above[i]) // 2) & 255
        elif kind == 4:
            p = left + above[i] - upper_left
            pa, pb, pc = abs(p - left), abs(p - above[i]), abs(p - upper_left)
            predictor = left if pa <= pb and pa <= pc else (above[i] if pb <= pc else upper_left)
            out[i] = (out[i] + predictor) & 255
        else:
            raise ValueError(f"unknown PNG filter type {kind}")
    return out.astype(np.uint8)


def read_png(path: StrPath) -> np.ndarray:
    """An 8-bit RGB or RGBA, non-interlaced PNG (what browsers' screenshots are) as an (H, W, 3)
    uint8 array (alpha dropped). Raises ValueError naming the file for any other PNG, OSError
    when it cannot be read."""
    image = read_png_channels(path)
    if image.shape[2] < 3:
        raise ValueError(f"{os.fspath(path)}: only 8-bit RGB/RGBA non-interlaced PNGs are read "
                         "(a grey one)")
    return image[..., :3]


def read_png_channels(path: StrPath) -> np.ndarray:
    """An 8-bit grey, RGB or RGBA non-interlaced PNG as an (H, W, channels) uint8 array, every
    channel kept (the SVBRDF maps' mask.png is grey, specular.png's alpha is F90). Raises
    ValueError naming the file for another or a damaged PNG, OSError when it cannot be read."""
    name = os.fspath(path)
    with open(name, "rb") as file:
        data = file.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{name}: not a PNG file")
    position = 8
    header: tuple[int, ...] | None = None
    compressed: list[bytes] = []
    while position + 8 <= len(data):
        (length,) = struct.unpack(">I", data[position : position + 4])
        kind = data[position + 4 : position + 8]
        body = data[position + 8 : position + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            compressed.append(body)
        elif kind == b"IEND":
            break
        position += 12 + length
    if header is None:
        raise ValueError(f"{name}: a PNG without a header")
    width, height, depth, colour, _, _, interlace = header
    channels = {0: 1, 2: 3, 6: 4}.get(colour)
    if depth != 8 or channels is None or interlace != 0:
        raise ValueError(
            f"{name}: only 8-bit grey/RGB/RGBA non-interlaced PNGs are read (depth {depth}, "
            f"colour type {colour}, interlace {interlace})"
        )
    stride = width * channels
    try:
        raw = np.frombuffer(zlib.decompress(b"".join(compressed)), dtype=np.uint8)
    except zlib.error as e:
        raise ValueError(f"{name}: damaged or truncated PNG data ({e})") from None
    if raw.size != height * (stride + 1):
        raise ValueError(f"{name}: truncated PNG ({raw.size} of {height * (stride + 1)} bytes)")
    raw = raw.reshape(height, stride + 1)
    image = np.zeros((height, stride), dtype=np.uint8)
    previous = np.zeros(stride, dtype=np.uint8)
    for y in range(height):
        image[y] = _unfilter(int(raw[y, 0]), raw[y, 1:], previous, channels)
        previous = image[y]
    return image.reshape(height, width, channels)
