"""An ABRDF table in memory: 81 light x 81 view directions x RGB, BRDF in 1/sr, linear."""

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from slicecap.interpolation import evaluate

TABLE_SHAPE = (81, 81, 3)


@dataclass
class Abrdf:
    """A full table `values[light, view, channel]` (float32, Bonn order) and its `slicecap:*`
    header attributes without the prefix (e.g. "method", "material")."""

    values: np.ndarray
    attributes: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.values = np.ascontiguousarray(self.values, dtype=np.float32)
        if self.values.shape != TABLE_SHAPE:
            raise ValueError(f"an ABRDF table has shape (81, 81, 3), got {self.values.shape}")

    def evaluate(self, light_deg: ArrayLike, view_deg: ArrayLike) -> np.ndarray:
        """RGB BRDF at (..., 2) light and view directions (theta_deg, phi_deg); see
        slicecap.interpolation.evaluate."""
        return evaluate(self.values, light_deg, view_deg)

    def is_reciprocal(self, relative_tolerance: float = 1e-6) -> bool:
        """True if swapping light and view changes no value by more than the tolerance (relative
        to the table's largest value)."""
        scale = max(float(np.max(np.abs(self.values))), float(np.finfo(np.float32).tiny))
        swapped = np.transpose(self.values, (1, 0, 2))
        return bool(np.max(np.abs(self.values - swapped)) <= relative_tolerance * scale)
