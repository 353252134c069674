"""The Bonn 81-direction hemisphere grid (docs/method.md §1.1): rings, index order, unit vectors."""

import numbers
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

DIRECTION_COUNT = 81

# A BRDF as a function: brdf(to_light, to_view) maps (N, 3) unit vectors in the surface frame to
# (N, 3) RGB values in 1/sr.
Brdf = Callable[[np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Ring:
    """One elevation ring: it starts at azimuth 0 and steps 360 / count degrees."""

    theta_deg: int
    count: int
    first_index: int

    @property
    def step_deg(self) -> float:
        return 360.0 / self.count


RINGS = (
    Ring(0, 1, 0),
    Ring(15, 6, 1),
    Ring(30, 12, 7),
    Ring(45, 18, 19),
    Ring(60, 20, 37),
    Ring(75, 24, 57),
)

RING_THETA_DEG = np.array([r.theta_deg for r in RINGS], dtype=np.float64)
RING_COUNT = np.array([r.count for r in RINGS], dtype=np.int64)
RING_FIRST_INDEX = np.array([r.first_index for r in RINGS], dtype=np.int64)


def _direction_table() -> np.ndarray:
    directions = [(float(r.theta_deg), k * r.step_deg) for r in RINGS for k in range(r.count)]
    return np.array(directions, dtype=np.float64)


GRID_DIRECTIONS_DEG = _direction_table()
"""(81, 2) array of (theta_deg, phi_deg) in the Bonn index order."""


def is_whole_number(value: object) -> bool:
    """An integer of any integral type, but not a bool (True would index as 1)."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def direction_of_index(index: int) -> tuple[float, float]:
    """(theta_deg, phi_deg) of a grid index; raises IndexError outside 0..80, TypeError for what
    is not a whole number."""
    if not is_whole_number(index):
        raise TypeError(f"a Bonn direction index is a whole number in 0..80, got {index!r}")
    if not 0 <= index < DIRECTION_COUNT:
        raise IndexError(f"Bonn direction index {index} is outside 0..80")
    theta_deg, phi_deg = GRID_DIRECTIONS_DEG[index]
    return float(theta_deg), float(phi_deg)


def wrap_deg360(azimuth_deg: ArrayLike) -> np.ndarray:
    """Azimuths taken mod 360 into [0, 360), as the C++ wrapDeg360 (fmod, then + 360)."""
    wrapped = np.fmod(np.asarray(azimuth_deg, dtype=np.float64), 360.0)
    wrapped = np.where(wrapped < 0.0, wrapped + 360.0, wrapped)
    # fmod of a tiny negative number plus 360 can round up to exactly 360.
    return np.where(wrapped >= 360.0, 0.0, wrapped)


def to_unit_vectors(directions_deg: np.ndarray) -> np.ndarray:
    """(..., 2) (theta_deg, phi_deg) -> (..., 3) unit vectors, azimuth counter-clockwise from x."""
    directions_deg = np.asarray(directions_deg, dtype=np.float64)
    theta = np.radians(directions_deg[..., 0])
    phi = np.radians(directions_deg[..., 1])
    return np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1
    )


def to_directions_deg(vectors: np.ndarray) -> np.ndarray:
    """(..., 3) vectors (need not be unit) -> (..., 2) (theta_deg, phi_deg), azimuth in [0, 360)."""
    vectors = np.asarray(vectors, dtype=np.float64)
    length = np.linalg.norm(vectors, axis=-1)
    if np.any(~(length > 0.0)):
        raise ValueError("to_directions_deg: zero-length or non-finite vector")
    z = np.clip(vectors[..., 2] / length, -1.0, 1.0)
    theta_deg = np.degrees(np.arccos(z))
    on_axis = (vectors[..., 0] == 0.0) & (vectors[..., 1] == 0.0)
    phi_deg = wrap_deg360(np.degrees(np.arctan2(vectors[..., 1], vectors[..., 0])))
    phi_deg = np.where(on_axis, 0.0, phi_deg)
    return np.stack([theta_deg, phi_deg], axis=-1)


def tabulate(brdf: Brdf) -> np.ndarray:
    """The (81, 81, 3) float32 table of `brdf(to_light, to_view)`, a function of (N, 3) unit
    vectors returning (N, 3) RGB values in 1/sr: row = light index, column = view index."""
    vectors = to_unit_vectors(GRID_DIRECTIONS_DEG)
    light = np.repeat(vectors, DIRECTION_COUNT, axis=0)
    view = np.tile(vectors, (DIRECTION_COUNT, 1))
    values = np.asarray(brdf(light, view), dtype=np.float64)
    return values.reshape(DIRECTION_COUNT, DIRECTION_COUNT, 3).astype(np.float32)
