"""The paper's 8-bit metrics (docs/method.md §6.1; lib/eval/metrics) applied to two renderings.

Both images are divided by one exposure taken from the reference, clipped to [0, 1],
sRGB-encoded, x255 and rounded; then the mean CIE76 dE over the masked pixels (sRGB D65 to
L*a*b* with the sRGB white), the RMSE of the 8-bit values and PSNR = 20 log10(255 / RMSE), at most
100 dB. Unlike the tables' metrics the exposure is a high percentile of the reference, not its
maximum: one Monte Carlo firefly would otherwise darken both images and hide every difference.
"""

from dataclasses import dataclass

import numpy as np

MAX_PSNR_DB = 100.0
EXPOSURE_PERCENTILE = 99.5
_SRGB_TO_XYZ = np.array(
    [
        [0.4124564, 0.3575761, 0.1804375],
        [0.2126729, 0.7151522, 0.0721750],
        [0.0193339, 0.1191920, 0.9503041],
    ]
)


@dataclass(frozen=True)
class ImageMetrics:
    delta_e: float
    rmse: float
    psnr_db: float


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    linear = np.asarray(linear, dtype=np.float64)
    return np.where(
        linear <= 0.0031308,
        12.92 * linear,
        1.055 * np.power(np.maximum(linear, 0.0031308), 1 / 2.4) - 0.055,
    )


def srgb_decode(encoded: np.ndarray) -> np.ndarray:
    encoded = np.asarray(encoded, dtype=np.float64)
    return np.where(encoded <= 0.04045, encoded / 12.92, ((encoded + 0.055) / 1.055) ** 2.4)


def to_8bit(linear: np.ndarray, exposure: float) -> np.ndarray:
    """Linear RGB divided by `exposure`, clipped, sRGB-encoded, x255, rounded (half away from 0
    as std::lround)."""
    normalised = np.clip(np.asarray(linear, dtype=np.float64) / exposure, 0.0, 1.0)
    return np.floor(srgb_encode(normalised) * 255.0 + 0.5).astype(np.uint8)


def _lab(srgb8: np.ndarray) -> np.ndarray:
    xyz = srgb_decode(srgb8 / 255.0) @ _SRGB_TO_XYZ.T
    xyz /= _SRGB_TO_XYZ.sum(axis=1)
    delta = 6.0 / 29.0
    f = np.where(xyz > delta**3, np.cbrt(xyz), xyz / (3 * delta**2) + 4.0 / 29.0)
    return np.stack(
        [116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])],
        axis=-1,
    )


def delta_e_8bit(reference8: np.ndarray, test8: np.ndarray) -> np.ndarray:
    """Per-pixel CIE76 dE between two (..., 3) 8-bit sRGB images (as compare_images uses)."""
    return np.linalg.norm(_lab(np.asarray(reference8)) - _lab(np.asarray(test8)), axis=-1)


def exposure_of(reference: np.ndarray, mask: np.ndarray | None = None) -> float:
    """The reference's EXPOSURE_PERCENTILE-th percentile of channel values (masked pixels)."""
    values = reference if mask is None else reference[mask]
    exposure = float(np.percentile(values, EXPOSURE_PERCENTILE))
    if not exposure > 0.0:
        raise ValueError("the reference rendering has no positive value")
    return exposure


def compare_images(
    reference: np.ndarray, test: np.ndarray, mask: np.ndarray | None = None
) -> ImageMetrics:
    """dE, RMSE and PSNR of `test` against `reference` (H, W, 3 linear), over `mask` pixels.
    Raises ValueError for images of other shapes, a mask of another size, or a non-finite masked
    pixel (which the 8-bit encoding would turn into 0 without a word)."""
    reference = np.asarray(reference, dtype=np.float64)
    test = np.asarray(test, dtype=np.float64)
    if reference.ndim != 3 or reference.shape[2] != 3:
        raise ValueError(f"images must be (H, W, 3), got {reference.shape}")
    if reference.shape != test.shape:
        raise ValueError(f"images differ in shape: {reference.shape} vs {test.shape}")
    if mask is None:
        mask = np.ones(reference.shape[:2], dtype=bool)
    mask = np.asarray(mask, dtype=bool)
    if mask.shape != reference.shape[:2]:
        raise ValueError(f"the mask is {mask.shape}, the images {reference.shape[:2]}")
    for name, image in (("reference", reference), ("test", test)):
        bad = np.argwhere(~np.isfinite(image) & mask[..., None])
        if len(bad):
            row, column, channel = bad[0]
            raise ValueError(
                f"the {name} image has a non-finite value at row {row}, column {column}, "
                f"channel {channel}"
            )
    exposure = exposure_of(reference, mask)
    ref8 = to_8bit(reference[mask], exposure)
    test8 = to_8bit(test[mask], exposure)
    rmse = float(np.sqrt(np.mean((ref8.astype(float) - test8.astype(float)) ** 2)))
    psnr = MAX_PSNR_DB if rmse == 0 else min(MAX_PSNR_DB, 20 * np.log10(255.0 / rmse))
    delta_e = float(np.mean(np.linalg.norm(_lab(ref8) - _lab(test8), axis=-1)))
    return ImageMetrics(delta_e=delta_e, rmse=rmse, psnr_db=float(psnr))
