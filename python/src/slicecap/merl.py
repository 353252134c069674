"""Export of isotropic tables to the MERL binary BRDF format, and the MERL lookup to check it.

The MERL layout (Matusik et al. 2003, the MERL database and its BRDFRead.cpp): three int32
dimensions 90, 90, 180, then 3 x 90 x 90 x 180 float64 values, channel-major, indexed by
[theta_half][theta_diff][phi_diff] in the Rusinkiewicz half/difference angles; theta_half is
binned by the square root of theta_half / 90 deg, phi_diff covers [0, 180) deg (reciprocity), and
the stored numbers are the BRDF divided by 1/1500, 1.15/1500 and 1.66/1500 for R, G, B.
"""

import math
import os

import numpy as np
from numpy.typing import ArrayLike

from slicecap.abrdf import TABLE_SHAPE, Abrdf
from slicecap.abrdf_exr import SlicecapFileError, first_invalid_value
from slicecap.grid import RINGS, to_directions_deg
from slicecap.isotropic import IsotropicTable
from slicecap.paths import StrPath, write_replacing

THETA_HALF_BINS = 90
THETA_DIFF_BINS = 90
PHI_DIFF_BINS = 180
SCALE = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])
MAX_ANISOTROPY = 0.05


def _rotate_z(v: np.ndarray, angle_rad: ArrayLike) -> np.ndarray:
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1], v[..., 2]], -1)


def _rotate_y(v: np.ndarray, angle_rad: ArrayLike) -> np.ndarray:
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.stack([c * v[..., 0] + s * v[..., 2], v[..., 1], -s * v[..., 0] + c * v[..., 2]], -1)


def half_diff_angles(to_light: np.ndarray, to_view: np.ndarray) -> tuple[np.ndarray, ...]:
    """(theta_half, theta_diff, phi_diff) in radians of unit vectors, as MERL's
    std_coords_to_half_diff_coords (the light is MERL's "in" direction)."""
    half = to_light + to_view
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    theta_half = np.arccos(np.clip(half[..., 2], -1.0, 1.0))
    phi_half = np.arctan2(half[..., 1], half[..., 0])
    diff = _rotate_y(_rotate_z(to_light, -phi_half), -theta_half)
    theta_diff = np.arccos(np.clip(diff[..., 2], -1.0, 1.0))
    phi_diff = np.arctan2(diff[..., 1], diff[..., 0])
    return theta_half, theta_diff, phi_diff


def directions_of_half_diff(
    theta_half_rad: ArrayLike,
    phi_half_rad: ArrayLike,
    theta_diff_rad: ArrayLike,
    phi_diff_rad: ArrayLike,
) -> tuple[np.ndarray, np.ndarray]:
    """(to_light, to_view) unit vectors of half/difference angles in radians (the inverse of the
    above)."""
    diff = np.stack(
        [
            np.sin(theta_diff_rad) * np.cos(phi_diff_rad),
            np.sin(theta_diff_rad) * np.sin(phi_diff_rad),
            np.cos(theta_diff_rad),
        ],
        -1,
    )
    to_light = _rotate_z(_rotate_y(diff, theta_half_rad), phi_half_rad)
    half = np.stack(
        [
            np.sin(theta_half_rad) * np.cos(phi_half_rad),
            np.sin(theta_half_rad) * np.sin(phi_half_rad),
            np.cos(theta_half_rad),
        ],
        -1,
    )
    to_view = 2.0 * np.sum(half * to_light, axis=-1, keepdims=True) * half - to_light
    return to_light, to_view


def bin_indices(
    theta_half_rad: np.ndarray, theta_diff_rad: np.ndarray, phi_diff_rad: np.ndarray
) -> np.ndarray:
    """The flat MERL index of half/difference angles in radians (BRDFRead.cpp's nearest-bin
    rule)."""
    half_position = np.sqrt(
        np.maximum(theta_half_rad, 0.0) / (np.pi / 2) * THETA_HALF_BINS * THETA_HALF_BINS
    )
    i = np.clip(half_position.astype(np.int64), 0, THETA_HALF_BINS - 1)
    j = np.clip(
        (theta_diff_rad / (np.pi / 2) * THETA_DIFF_BINS).astype(np.int64), 0, THETA_DIFF_BINS - 1
    )
    phi_diff_rad = np.where(phi_diff_rad < 0.0, phi_diff_rad + np.pi, phi_diff_rad)
    k = np.clip((phi_diff_rad / np.pi * PHI_DIFF_BINS).astype(np.int64), 0, PHI_DIFF_BINS - 1)
    return (i * THETA_DIFF_BINS + j) * PHI_DIFF_BINS + k


def grid_anisotropy(table: np.ndarray) -> float:
    """Relative RMS change of the table under the rotations about the normal that map a pair of
    rings onto itself (e.g. every 15 deg for 75/75): 0 for an isotropic material, up to float
    rounding; no interpolation is involved."""
    differences, norms = 0.0, 0.0
    for ring_a in RINGS:
        for ring_b in RINGS:
            if ring_a.count == 1 and ring_b.count == 1:
                continue  # pole to pole: no rotation changes it
            step_a, step_b = 360 // ring_a.count, 360 // ring_b.count
            rotation = math.lcm(
                step_a if ring_a.count > 1 else 1, step_b if ring_b.count > 1 else 1
            )
            block = table[
                ring_a.first_index : ring_a.first_index + ring_a.count,
                ring_b.first_index : ring_b.first_index + ring_b.count,
            ].astype(np.float64)
            for angle in range(rotation, 360, rotation):
                shift_a = angle // step_a if ring_a.count > 1 else 0
                shift_b = angle // step_b if ring_b.count > 1 else 0
                rotated = np.roll(np.roll(block, -shift_a, axis=0), -shift_b, axis=1)
                differences += np.sum((rotated - block) ** 2)
                norms += np.sum(block**2)
    return math.sqrt(differences / norms) if norms > 0 else 0.0


def merl_values_of_table(table: np.ndarray) -> np.ndarray:
    """(3, 90, 90, 180) BRDF values at the MERL bin centres, read from the table as an isotropic
    material (slicecap.isotropic); 0 where the light or the view is below the horizon."""
    theta_half = ((np.arange(THETA_HALF_BINS) + 0.5) / THETA_HALF_BINS) ** 2 * (np.pi / 2)
    theta_diff = (np.arange(THETA_DIFF_BINS) + 0.5) / THETA_DIFF_BINS * (np.pi / 2)
    phi_diff = (np.arange(PHI_DIFF_BINS) + 0.5) / PHI_DIFF_BINS * np.pi
    th, td, pd = np.meshgrid(theta_half, theta_diff, phi_diff, indexing="ij")
    to_light, to_view = directions_of_half_diff(th, 0.0, td, pd)
    visible = (to_light[..., 2] > 0.0) & (to_view[..., 2] > 0.0)
    light_deg = to_directions_deg(to_light[visible])
    view_deg = to_directions_deg(to_view[visible])
    values = np.zeros(th.shape + (3,))
    values[visible] = IsotropicTable(table).evaluate(
        light_deg[:, 0], view_deg[:, 0], view_deg[:, 1] - light_deg[:, 1]
    )
    return np.moveaxis(values, -1, 0)


def export_merl(
    path: StrPath, table: Abrdf | ArrayLike, *, allow_anisotropic: bool = False
) -> float:
    """Writes an (81, 81, 3) table (or an Abrdf) as a MERL .binary file and returns its grid
    anisotropy. Raises ValueError for a table of another shape, with a non-finite or negative
    value, or anisotropic beyond MAX_ANISOTROPY (MERL holds isotropic materials only;
    allow_anisotropic=True exports the azimuthal average instead), and SlicecapFileError naming
    the file when it cannot be written."""
    values = np.asarray(getattr(table, "values", table), dtype=np.float64)
    if values.shape != TABLE_SHAPE:
        raise ValueError(f"an ABRDF table has shape (81, 81, 3), got {values.shape}")
    problem = first_invalid_value(values)
    if problem:
        # It would spread through the interpolation or vanish between bins, without a word; a
        # negative one MERL readers take for "no measurement".
        raise ValueError(f"the table has a {problem}")
    anisotropy = grid_anisotropy(values)
    if anisotropy > MAX_ANISOTROPY and not allow_anisotropic:
        raise ValueError(
            f"the table is anisotropic ({100 * anisotropy:.1f} % change under rotations, above "
            f"{100 * MAX_ANISOTROPY:.0f} %); MERL holds isotropic materials only "
            "(allow_anisotropic or --allow-anisotropic exports its azimuthal average)"
        )
    merl = merl_values_of_table(values) / SCALE[:, None, None, None]
    try:

        def write(target: str) -> None:
            with open(target, "wb") as file:
                np.array([THETA_HALF_BINS, THETA_DIFF_BINS, PHI_DIFF_BINS], "<i4").tofile(file)
                merl.astype("<f8").tofile(file)

        write_replacing(path, write)
    except OSError as e:
        raise SlicecapFileError(f"{os.fspath(path)}: cannot write MERL file: {e.strerror}") from e
    return anisotropy


def read_merl(path: StrPath) -> np.ndarray:
    """The (3, 90, 90, 180) BRDF values (1/sr, scaled back) of a MERL .binary file. Raises
    SlicecapFileError naming the file when it is missing, short or has other dimensions."""
    try:
        raw = open(path, "rb").read()
    except OSError as e:
        raise SlicecapFileError(f"{os.fspath(path)}: cannot read MERL file: {e.strerror}") from e
    expected_dims = (THETA_HALF_BINS, THETA_DIFF_BINS, PHI_DIFF_BINS)
    count = 3 * THETA_HALF_BINS * THETA_DIFF_BINS * PHI_DIFF_BINS
    if len(raw) < 12 or tuple(np.frombuffer(raw[:12], "<i4")) != expected_dims:
        raise SlicecapFileError(
            f"{os.fspath(path)}: not a MERL BRDF (dimensions must be 90 90 180)"
        )
    if len(raw) != 12 + 8 * count:
        raise SlicecapFileError(
            f"{os.fspath(path)}: MERL file has {len(raw)} bytes, expected {12 + 8 * count}"
        )
    data = np.frombuffer(raw[12:], "<f8").reshape(3, *expected_dims)
    return data * SCALE[:, None, None, None]


def merl_lookup(merl: np.ndarray, to_light: np.ndarray, to_view: np.ndarray) -> np.ndarray:
    """(..., 3) RGB of MERL values at unit vectors (nearest bin; negative entries read as 0)."""
    index = bin_indices(*half_diff_angles(to_light, to_view))
    flat = merl.reshape(3, -1)
    return np.maximum(np.moveaxis(flat[:, index], 0, -1), 0.0)
