"""The sampling histograms (numpy side of the plugin's importance sampling)."""

import numpy as np
from mitsuba_support import phong

from slicecap import tabulate
from slicecap.sampling import COS_BINS, PHI_BINS, bin_of, build_sampling_tables


def test_histograms_are_normalised_and_follow_f_cos():
    table = tabulate(phong([0.1, 0.1, 0.1], [0.8, 0.8, 0.8], 30))
    tables = build_sampling_tables(table)
    np.testing.assert_allclose(tables.pmf.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_array_equal(tables.cdf[:, -1], 1.0)
    assert tables.bin_solid_angle_sr * COS_BINS * PHI_BINS == np.pi * 2
    # Seen from (45, 0), the Phong lobe points at the mirror direction (45, 180): its bin is
    # among the heaviest of that view's histogram.
    heaviest = np.argsort(tables.pmf[19])[-20:]
    assert bin_of(np.cos(np.radians(45.0)), 180.0) in heaviest


def test_light_side_tables_are_the_transpose():
    rng = np.random.default_rng(0)
    table = rng.uniform(0, 1, (81, 81, 3)).astype(np.float32)
    swapped = np.ascontiguousarray(np.transpose(table, (1, 0, 2)))
    np.testing.assert_allclose(
        build_sampling_tables(table, "light").pmf, build_sampling_tables(swapped, "view").pmf
    )


def test_a_black_direction_samples_uniformly():
    tables = build_sampling_tables(np.zeros((81, 81, 3), np.float32))
    np.testing.assert_allclose(tables.pmf, 1.0 / (COS_BINS * PHI_BINS))
