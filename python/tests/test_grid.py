"""The Bonn grid in Python: order, vectors, tabulation."""

import numpy as np
import pytest

from slicecap import direction_of_index, tabulate
from slicecap.grid import GRID_DIRECTIONS_DEG, to_directions_deg, to_unit_vectors


def test_index_order_matches_the_readme():
    assert direction_of_index(0) == (0.0, 0.0)
    assert direction_of_index(1) == (15.0, 0.0)
    assert direction_of_index(8) == (30.0, 30.0)
    assert direction_of_index(56) == (60.0, 342.0)
    assert direction_of_index(80) == (75.0, 345.0)
    with pytest.raises(IndexError, match="81 is outside 0..80"):
        direction_of_index(81)
    assert direction_of_index(np.int64(8)) == (30.0, 30.0)


def test_an_index_that_is_not_a_whole_number_is_refused():
    # 1.5 ended in numpy's "only integers, slices ... are valid indices"; True was index 1.
    for index in (1.5, True, "8"):
        with pytest.raises(TypeError, match=f"whole number in 0..80, got {index!r}"):
            direction_of_index(index)


def test_vectors_and_directions_round_trip():
    back = to_directions_deg(to_unit_vectors(GRID_DIRECTIONS_DEG))
    np.testing.assert_allclose(back, GRID_DIRECTIONS_DEG, atol=1e-9)
    np.testing.assert_allclose(to_unit_vectors([90.0, 90.0]), [0, 1, 0], atol=1e-15)


def test_tabulate_puts_lights_in_rows():
    def light_elevation_only(light, view):
        return np.repeat(light[:, 2:3], 3, axis=1)

    table = tabulate(light_elevation_only)
    assert table.shape == (81, 81, 3) and table.dtype == np.float32
    assert table[0, 80, 0] == 1.0
    assert table[80, 0, 0] == pytest.approx(np.cos(np.radians(75)))
