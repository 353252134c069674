"""Interpolation at arbitrary directions agrees with the C++ `slicecap::evaluate` on the shared
vectors (tests/vectors/grid_interpolation.json, written and checked by the C++ side)."""

import json

import numpy as np
import pytest
from conftest import VECTORS_FILE

from slicecap import evaluate
from slicecap.interpolation import direction_taps


@pytest.fixture(scope="module")
def vectors() -> dict:
    return json.loads(VECTORS_FILE.read_text())


def hash_table(definition: dict) -> np.ndarray:
    m0, m1, m2 = definition["multipliers"]
    modulus = definition["modulus"]
    light, view, channel = np.meshgrid(np.arange(81), np.arange(81), np.arange(3), indexing="ij")
    k = (light * m0 + view * m1 + channel * m2) % modulus
    return ((k + 1) / modulus).astype(np.float32)


def test_every_case_matches_the_cpp_values(vectors):
    table = hash_table(vectors["table"])
    cases = vectors["cases"]
    light = np.array([c["light"] for c in cases])
    view = np.array([c["view"] for c in cases])
    expected = np.array([c["rgb"] for c in cases])
    got = evaluate(table, light, view)
    worst = np.max(np.abs(got - expected) / np.abs(expected))
    wrong = [c for c, g in zip(cases, got, strict=True) if not np.allclose(g, c["rgb"], 1e-12)]
    assert worst < 1e-12, wrong
    assert {c["kind"] for c in cases} >= {"grid", "azimuth", "elevation", "pole", "wrap", "clamp"}


def test_one_case_at_a_time_gives_the_same_as_a_batch(vectors):
    table = hash_table(vectors["table"])
    for case in vectors["cases"][:12]:
        np.testing.assert_allclose(evaluate(table, case["light"], case["view"]), case["rgb"], 1e-12)


def test_invalid_directions_are_rejected_as_in_cpp(vectors):
    table = hash_table(vectors["table"])
    for case in vectors["invalid"]:
        with pytest.raises(ValueError, match="not on the upper hemisphere"):
            evaluate(table, case["light"], case["view"])
    with pytest.raises(ValueError, match="not on the upper hemisphere"):
        evaluate(table, [np.nan, 0.0], [30.0, 0.0])


def test_weights_sum_to_one_and_grid_directions_take_one_tap():
    theta, phi = np.meshgrid(np.arange(0, 90, 3.7), np.arange(-30, 400, 11.3), indexing="ij")
    _, weights = direction_taps(theta, phi)
    np.testing.assert_allclose(weights.sum(axis=-1), 1.0, atol=1e-12)
    from slicecap.grid import GRID_DIRECTIONS_DEG

    indices, weights = direction_taps(GRID_DIRECTIONS_DEG[:, 0], GRID_DIRECTIONS_DEG[:, 1])
    chosen = np.take_along_axis(indices, np.argmax(weights, axis=-1)[:, None], axis=-1)[:, 0]
    np.testing.assert_array_equal(chosen, np.arange(81))
    np.testing.assert_array_equal(np.max(weights, axis=-1), 1.0)


def test_directions_that_are_not_theta_phi_pairs_are_refused_naming_the_argument(vectors):
    table = hash_table(vectors["table"])
    # A unit vector was read as theta = 0.5 deg, phi = 0.5 deg, its z ignored.
    with pytest.raises(ValueError, match=r"light_deg must hold \(theta_deg, phi_deg\) .*\(3,\)"):
        evaluate(table, [0.5, 0.5, 0.707], [45.0, 180.0])
    with pytest.raises(ValueError, match=r"view_deg must hold .* got shape \(\)"):
        evaluate(table, [45.0, 0.0], 45.0)
    with pytest.raises(ValueError, match=r"view_deg must hold .* got shape \(2, 1\)"):
        evaluate(table, [[45.0, 0.0]], [[45.0], [180.0]])
