"""Tabulated importance sampling of a Bonn-grid table, built with numpy (the Mitsuba plugin only
looks these tables up).

For each of the 81 grid directions on the known side (the view, when rendering from the camera),
a histogram over the other side's hemisphere holds the mass of f * cos(theta) in bins uniform in
(cos theta, phi), i.e. of equal solid angle. Sampling picks one of the known direction's four
interpolation taps by its weight, a bin by its mass and a point in the bin uniformly, so the
density is the taps' weighted mixture of histograms: continuous in the known direction, like the
table's own interpolation. A small share of cosine-weighted sampling keeps every direction with
f > 0 reachable.
"""

from dataclasses import dataclass

import numpy as np

from slicecap.interpolation import direction_taps

COS_BINS = 24
PHI_BINS = 72
SUBSAMPLES = 2
COSINE_SHARE = 0.1


@dataclass(frozen=True)
class SamplingTables:
    """Per known grid direction k (rows), bin masses `pmf[k, a * PHI_BINS + b]` summing to 1 and
    their inclusive running sums `cdf`; bin a covers cos theta in [a, a + 1) / COS_BINS, bin b
    covers phi in [b, b + 1) * 360 / PHI_BINS degrees."""

    pmf: np.ndarray
    cdf: np.ndarray

    @property
    def bin_solid_angle_sr(self) -> float:
        return 2.0 * np.pi / (COS_BINS * PHI_BINS)


def _bin_sample_directions_deg() -> np.ndarray:
    """(COS_BINS * PHI_BINS, SUBSAMPLES**2, 2) directions at stratified points inside each bin."""
    offsets = (np.arange(SUBSAMPLES) + 0.5) / SUBSAMPLES
    cos_theta = (np.arange(COS_BINS)[:, None] + offsets[None, :]) / COS_BINS
    phi_deg = (np.arange(PHI_BINS)[:, None] + offsets[None, :]) * 360.0 / PHI_BINS
    theta_deg = np.degrees(np.arccos(cos_theta))
    grid_theta = np.broadcast_to(
        theta_deg[:, None, :, None], (COS_BINS, PHI_BINS, SUBSAMPLES, SUBSAMPLES)
    )
    grid_phi = np.broadcast_to(
        phi_deg[None, :, None, :], (COS_BINS, PHI_BINS, SUBSAMPLES, SUBSAMPLES)
    )
    directions = np.stack([grid_theta, grid_phi], axis=-1)
    return directions.reshape(COS_BINS * PHI_BINS, SUBSAMPLES * SUBSAMPLES, 2)


def build_sampling_tables(table: np.ndarray, known_side: str = "view") -> SamplingTables:
    """Histograms of f * cos over the unknown side for each grid direction of the known side
    ("view": sample lights for a given view, as a camera path does; "light": the reverse)."""
    if known_side not in ("view", "light"):
        raise ValueError(f"known_side must be 'view' or 'light', got {known_side!r}")
    oriented = table if known_side == "view" else np.transpose(table, (1, 0, 2))
    # The known side is always a grid direction, so only the unknown side needs interpolating.
    gray = np.asarray(oriented, dtype=np.float64).mean(axis=-1)
    unknown_deg = _bin_sample_directions_deg()
    indices, weights = direction_taps(unknown_deg[..., 0], unknown_deg[..., 1])
    value = np.einsum("bst,bstk->bsk", weights, gray[indices])
    cos_theta = np.cos(np.radians(unknown_deg[..., 0]))
    mass = np.maximum(value, 0.0) * cos_theta[..., None]
    pmf = mass.mean(axis=1).T
    totals = pmf.sum(axis=1, keepdims=True)
    # A direction that reflects nothing anywhere samples uniformly (the cosine share covers it).
    pmf = np.where(totals > 0, pmf / np.where(totals > 0, totals, 1.0), 1.0 / pmf.shape[1])
    cdf = np.cumsum(pmf, axis=1)
    cdf[:, -1] = 1.0
    return SamplingTables(pmf=pmf, cdf=cdf)


def bin_of(cos_theta: np.ndarray, phi_deg: np.ndarray) -> np.ndarray:
    """The flat bin index of directions (numpy reference of the plugin's lookup)."""
    a = np.clip(np.floor(cos_theta * COS_BINS), 0, COS_BINS - 1).astype(np.int64)
    b = np.clip(np.floor(np.mod(phi_deg, 360.0) / 360.0 * PHI_BINS), 0, PHI_BINS - 1).astype(
        np.int64
    )
    return a * PHI_BINS + b
