"""The paper's 8-bit metrics on renderings, the PNG writer and the label font."""

import zlib

import numpy as np
import pytest

from slicecap.bitmap_font import text_mask
from slicecap.image_metrics import compare_images, to_8bit
from slicecap.png import read_png_size, write_png


def test_identical_images_score_zero_and_the_maximum_psnr():
    image = np.random.default_rng(0).uniform(0, 2, (8, 8, 3))
    metrics = compare_images(image, image)
    assert metrics.delta_e == 0 and metrics.rmse == 0 and metrics.psnr_db == 100.0


def test_half_brightness_gives_the_hand_computed_figures():
    reference = np.ones((4, 4, 3))
    # Exposure 1: 255 against round(255 * srgb(0.5)) = 188, so RMSE 67 and PSNR 11.61 dB; in
    # L*a*b* grey 255 is L* 100 and grey 188 (linear 0.5028) is L* 116 * 0.5028^(1/3) - 16 = 76.24.
    metrics = compare_images(reference, 0.5 * reference)
    assert to_8bit(np.array([0.5]), 1.0)[0] == 188
    assert metrics.rmse == pytest.approx(67.0)
    assert metrics.psnr_db == pytest.approx(20 * np.log10(255 / 67), abs=1e-9)
    assert metrics.delta_e == pytest.approx(100 - 76.24, abs=0.02)


def test_non_finite_pixels_and_mismatched_masks_are_refused():
    image = np.random.default_rng(1).uniform(0, 2, (8, 8, 3))
    broken = image.copy()
    broken[2, 5, 1] = np.nan
    # A NaN in the test image was encoded as 0 and scored; in the reference it was reported as
    # "the reference rendering has no positive value".
    with pytest.raises(ValueError, match="test image has a non-finite value at row 2, column 5"):
        compare_images(image, broken)
    with pytest.raises(ValueError, match="reference image has a non-finite value at row 2"):
        compare_images(broken, image)
    outside = np.ones((8, 8), dtype=bool)
    outside[2, 5] = False
    assert compare_images(image, broken, outside).rmse == 0  # not a compared pixel
    with pytest.raises(ValueError, match=r"the mask is \(4, 4\), the images \(8, 8\)"):
        compare_images(image, image, np.ones((4, 4), dtype=bool))
    with pytest.raises(ValueError, match=r"images must be \(H, W, 3\), got \(8, 8\)"):
        compare_images(image[..., 0], image[..., 0])


def test_the_mask_selects_the_compared_pixels():
    reference = np.ones((4, 4, 3))
    test = reference.copy()
    test[0, 0] = 0.0
    mask = np.ones((4, 4), dtype=bool)
    assert compare_images(reference, test, mask).rmse > 0
    mask[0, 0] = False
    assert compare_images(reference, test, mask).rmse == 0


def test_png_is_written_with_valid_chunks(tmp_path):
    image = np.zeros((5, 7, 3), dtype=np.uint8)
    image[1, 2] = (255, 128, 3)
    write_png(tmp_path / "x.png", image)
    assert read_png_size(tmp_path / "x.png") == (7, 5)
    data = (tmp_path / "x.png").read_bytes()
    start = data.index(b"IDAT") + 4
    length = int.from_bytes(data[start - 8 : start - 4], "big")
    rows = np.frombuffer(zlib.decompress(data[start : start + length]), np.uint8).reshape(5, 22)
    assert tuple(rows[1, 1 + 3 * 2 : 1 + 3 * 3]) == (255, 128, 3)


def test_text_masks_have_one_glyph_per_character():
    mask = text_mask("dE 1.5", scale=1)
    assert mask.shape == (7, 6 * 6)
    assert mask[:, :5].any() and not mask[:, 12:17].any()  # 'D' inked, ' ' blank
