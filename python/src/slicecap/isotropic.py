"""Isotropic reading of a Bonn-grid table: values as a function of (theta_i, theta_v, phi_v -
phi_i), for exports to isotropic formats (MERL).

On a pair of rings with azimuth steps a and b, the grid holds the azimuth difference at every
multiple of gcd(a, b) (2 deg for 45/60, 15 deg for 75/75), so an isotropic material is known far
more densely in the difference than along any ring. Each pair's entries are averaged per
difference, interpolated linearly (periodically) in the difference, and linearly in the two
elevations as slicecap.interpolation does (the 75 deg ring above 75). At grid pairs of an
isotropic table this reproduces the table exactly.
"""

import math

import numpy as np
from numpy.typing import ArrayLike

from slicecap.grid import RINGS, Ring, wrap_deg360


def _ring_step_deg(ring: Ring) -> int:
    return 360 // ring.count


def _pair_profile(table: np.ndarray, ring_a: Ring, ring_b: Ring) -> tuple[float, np.ndarray]:
    """(spacing_deg, (360 / spacing, 3) mean value per azimuth difference) of a ring pair."""
    poles = ring_a.count == 1 or ring_b.count == 1
    spacing = 360 if poles else math.gcd(_ring_step_deg(ring_a), _ring_step_deg(ring_b))
    sums = np.zeros((360 // spacing, 3))
    counts = np.zeros(360 // spacing)
    for p in range(ring_a.count):
        for q in range(ring_b.count):
            difference = (q * _ring_step_deg(ring_b) - p * _ring_step_deg(ring_a)) % 360
            k = 0 if poles else difference // spacing
            sums[k] += table[ring_a.first_index + p, ring_b.first_index + q]
            counts[k] += 1
    return float(spacing), sums / counts[:, None]


class IsotropicTable:
    """An (81, 81, 3) table read as an isotropic material (see the module's note)."""

    def __init__(self, table: ArrayLike) -> None:
        table = np.asarray(table, dtype=np.float64)
        count = len(RINGS)
        self.spacing_deg = np.zeros((count, count))
        self.length = np.zeros((count, count), dtype=np.int64)
        self.offset = np.zeros((count, count), dtype=np.int64)
        profiles: list[np.ndarray] = []
        for a, ring_a in enumerate(RINGS):
            for b, ring_b in enumerate(RINGS):
                spacing, profile = _pair_profile(table, ring_a, ring_b)
                self.spacing_deg[a, b] = spacing
                self.length[a, b] = len(profile)
                self.offset[a, b] = sum(len(p) for p in profiles)
                profiles.append(profile)
        # Every pair's profile back to back, so a lookup is a few gathers for all directions.
        self.profiles = np.concatenate(profiles)

    @staticmethod
    def _elevation_taps(theta_deg: np.ndarray) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
        upper = np.clip(np.ceil(theta_deg / 15.0).astype(np.int64), 1, 5)
        t = np.clip((theta_deg - 15.0 * (upper - 1)) / 15.0, 0.0, 1.0)
        return ((upper - 1, 1.0 - t), (upper, t))

    def evaluate(
        self, theta_light_deg: ArrayLike, theta_view_deg: ArrayLike, phi_difference_deg: ArrayLike
    ) -> np.ndarray:
        """(..., 3) BRDF at light and view elevations and azimuth difference phi_v - phi_i."""
        theta_light_deg, theta_view_deg, difference = np.broadcast_arrays(
            np.asarray(theta_light_deg, float),
            np.asarray(theta_view_deg, float),
            wrap_deg360(phi_difference_deg),
        )
        result = np.zeros(theta_light_deg.shape + (3,))
        for ring_l, weight_l in self._elevation_taps(theta_light_deg):
            for ring_v, weight_v in self._elevation_taps(theta_view_deg):
                length = self.length[ring_l, ring_v]
                offset = self.offset[ring_l, ring_v]
                position = difference / self.spacing_deg[ring_l, ring_v]
                lower = np.floor(position).astype(np.int64)
                f = (position - lower)[..., None]
                value = (1 - f) * self.profiles[offset + lower % length] + f * self.profiles[
                    offset + (lower + 1) % length
                ]
                result += value * (weight_l * weight_v)[..., None]
        return result
