"""A table's value at any light and view directions: linear interpolation on the Bonn grid.

The same rule as the C++ `slicecap::evaluate` (lib/core/grid_interpolation): periodic linear in
azimuth on the two rings around the elevation, linear in elevation between them, the 75 deg ring
for anything above 75 (no extrapolation toward the horizon). tests/vectors/grid_interpolation.json,
written by the C++ code, holds both to the same numbers.
"""

import numpy as np
from numpy.typing import ArrayLike

from slicecap.grid import RING_COUNT, RING_FIRST_INDEX, RING_THETA_DEG, wrap_deg360

TAPS_PER_DIRECTION = 4


def _check_directions(theta_deg: np.ndarray, phi_deg: np.ndarray) -> None:
    bad = ~np.isfinite(theta_deg) | ~np.isfinite(phi_deg) | (theta_deg < 0.0)
    if np.any(bad):
        first = np.flatnonzero(bad.ravel())[0]
        theta, phi = theta_deg.ravel()[first], phi_deg.ravel()[first]
        raise ValueError(
            f"direction (theta {theta:f}, phi {phi:f}) deg is not on the upper hemisphere"
        )


def _ring_taps(ring: np.ndarray, phi_deg: np.ndarray) -> tuple[np.ndarray, ...]:
    """Two taps on each given ring: periodic linear between its neighbouring azimuths."""
    count = RING_COUNT[ring]
    position = wrap_deg360(phi_deg) / (360.0 / count)
    lower = np.floor(position)
    fraction = position - lower
    lower = lower.astype(np.int64)
    first = RING_FIRST_INDEX[ring]
    return first + lower % count, 1.0 - fraction, first + (lower + 1) % count, fraction


def direction_taps(theta_deg: ArrayLike, phi_deg: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Grid indices and weights, each of shape (..., 4), whose weighted sum is the value at the
    given directions; weights sum to 1 (some may be 0). Raises ValueError for a negative or
    non-finite elevation or a non-finite azimuth."""
    theta_deg = np.asarray(theta_deg, dtype=np.float64)
    phi_deg = np.asarray(phi_deg, dtype=np.float64)
    theta_deg, phi_deg = np.broadcast_arrays(theta_deg, phi_deg)
    _check_directions(theta_deg, phi_deg)
    # The upper ring is the first of rings 1..5 at or above theta; above 75 it stays at 5.
    upper = 1 + np.sum(theta_deg[..., None] > RING_THETA_DEG[1:5], axis=-1)
    lower = upper - 1
    span = RING_THETA_DEG[upper] - RING_THETA_DEG[lower]
    t = np.clip((theta_deg - RING_THETA_DEG[lower]) / span, 0.0, 1.0)
    lo_a, lo_wa, lo_b, lo_wb = _ring_taps(lower, phi_deg)
    hi_a, hi_wa, hi_b, hi_wb = _ring_taps(upper, phi_deg)
    indices = np.stack([lo_a, lo_b, hi_a, hi_b], axis=-1)
    weights = np.stack([(1 - t) * lo_wa, (1 - t) * lo_wb, t * hi_wa, t * hi_wb], axis=-1)
    return indices, weights


def _pairs(directions_deg: ArrayLike, name: str) -> np.ndarray:
    """(..., 2) directions as float64; a ValueError naming the argument for any other shape (a
    unit vector's three numbers would otherwise read as theta and phi in degrees)."""
    directions_deg = np.asarray(directions_deg, dtype=np.float64)
    if directions_deg.ndim == 0 or directions_deg.shape[-1] != 2:
        raise ValueError(
            f"{name} must hold (theta_deg, phi_deg) pairs, shape (..., 2); "
            f"got shape {directions_deg.shape}"
        )
    return directions_deg


def evaluate(table: ArrayLike, light_deg: ArrayLike, view_deg: ArrayLike) -> np.ndarray:
    """The interpolated RGB value of an (81, 81, 3) table (row = light, column = view) at light
    and view directions given as (..., 2) arrays of (theta_deg, phi_deg); returns (..., 3)
    float64. Raises ValueError for directions of another shape, or one below the horizon plane
    (theta < 0) or non-finite.
    """
    table = np.asarray(table)
    if table.shape != (81, 81, 3):
        raise ValueError(f"table must have shape (81, 81, 3), got {table.shape}")
    light_deg = _pairs(light_deg, "light_deg")
    view_deg = _pairs(view_deg, "view_deg")
    light_index, light_weight = direction_taps(light_deg[..., 0], light_deg[..., 1])
    view_index, view_weight = direction_taps(view_deg[..., 0], view_deg[..., 1])
    light_index, view_index = np.broadcast_arrays(light_index, view_index)
    light_weight, view_weight = np.broadcast_arrays(light_weight, view_weight)
    values = table.astype(np.float64)
    result = np.zeros(light_index.shape[:-1] + (3,), dtype=np.float64)
    for i in range(TAPS_PER_DIRECTION):
        for j in range(TAPS_PER_DIRECTION):
            weight = light_weight[..., i] * view_weight[..., j]
            result += values[light_index[..., i], view_index[..., j]] * weight[..., None]
    return result
