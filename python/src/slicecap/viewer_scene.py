"""The material viewer's scene (docs/material-viewer.md), shared by the HTML page's WebGL code
(viewer_page.js reads these numbers from the page) and the numpy renderer that checks it
(render.render_sphere_point_light): camera, point light, constant environment, surface frames.

World: y up, the object at the origin. The camera orbits at CAMERA_DISTANCE (yaw about y from +z,
pitch up from the horizontal plane) and looks at the origin with a FOV_DEG vertical field of view.
The point light sits at LIGHT_DISTANCE in the direction (azimuth about y from +z, elevation) and
has LIGHT_INTENSITY (W/sr): its radiance contribution is f cos_i I / d^2. The environment is a
constant radiance `env` all around; its contribution is env times the directional albedo of the
view direction (the BRDF's cos-weighted hemispherical integral, tabulated at the 81 grid
directions and interpolated like the table).

A surface's frame: z = normal, x = tangent = the table's azimuth-0 axis (the Bonn grid's x,
docs/method.md §1.2), y = normal x tangent. On the sphere the tangent runs along the parallels,
(0, 1, 0) x normal, so at the point facing +z it is +x (screen right at yaw 0).
"""

import math

import numpy as np

from slicecap.grid import GRID_DIRECTIONS_DEG, Brdf, to_directions_deg, to_unit_vectors
from slicecap.interpolation import direction_taps

CAMERA_DISTANCE = 4.6
FOV_DEG = 30.0
LIGHT_DISTANCE = 4.0
LIGHT_INTENSITY = 16.0
DEFAULTS = {"light_az": 35.0, "light_el": 35.0, "yaw": 0.0, "pitch": 15.0, "env": 0.15}
_ALBEDO_THETA_STEPS, _ALBEDO_PHI_STEPS = 45, 90
ALBEDO_STEPS = (_ALBEDO_THETA_STEPS, _ALBEDO_PHI_STEPS)  # also slicecap.albedo_table's


def orbit_direction(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """The unit vector at an azimuth about y (0 = +z, 90 = +x) and an elevation above the xz
    plane."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])


def camera_rays(size: int, yaw_deg: float, pitch_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """The camera's origin (3,) and unit ray directions (size, size, 3) through pixel centres,
    row 0 at the top, as the page's perspective projection (square viewport)."""
    origin = CAMERA_DISTANCE * orbit_direction(yaw_deg, pitch_deg)
    forward = -origin / np.linalg.norm(origin)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half_height = math.tan(math.radians(FOV_DEG) / 2)
    centres = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    x = centres[None, :, None] * half_height
    y = -centres[:, None, None] * half_height
    rays = forward + x * right + y * up
    return origin, rays / np.linalg.norm(rays, axis=-1, keepdims=True)


def sphere_frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Tangent and bitangent (..., 3) of the unit sphere at unit normals (..., 3); at the poles,
    where the parallels shrink to a point, the tangent is +x."""
    tangent = np.stack([normal[..., 2], np.zeros_like(normal[..., 0]), -normal[..., 0]], axis=-1)
    length = np.linalg.norm(tangent, axis=-1, keepdims=True)
    tangent = np.where(length > 1e-6, tangent / np.maximum(length, 1e-12), [1.0, 0.0, 0.0])
    return tangent, np.cross(normal, tangent)


def directional_albedo(brdf: Brdf) -> np.ndarray:
    """(81, 3): for each grid direction as the view, the integral of brdf(l, v) cos(theta_l) over
    the light hemisphere (midpoint rule, 45 x 90 cells): what a constant unit environment gives.
    `brdf(to_light, to_view)` takes and returns (N, 3) arrays."""
    theta = (np.arange(_ALBEDO_THETA_STEPS) + 0.5) * (math.pi / 2) / _ALBEDO_THETA_STEPS
    phi = (np.arange(_ALBEDO_PHI_STEPS) + 0.5) * (2 * math.pi) / _ALBEDO_PHI_STEPS
    theta, phi = np.meshgrid(theta, phi, indexing="ij")
    lights = np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1
    ).reshape(-1, 3)
    cell = (math.pi / 2 / _ALBEDO_THETA_STEPS) * (2 * math.pi / _ALBEDO_PHI_STEPS)
    weights = (np.cos(theta) * np.sin(theta)).reshape(-1) * cell
    albedo = np.zeros((len(GRID_DIRECTIONS_DEG), 3))
    for index, view in enumerate(to_unit_vectors(GRID_DIRECTIONS_DEG)):
        values = brdf(lights, np.broadcast_to(view, lights.shape))
        albedo[index] = weights @ values
    return albedo


def albedo_at(albedo: np.ndarray, to_view: np.ndarray) -> np.ndarray:
    """(N, 3) directional albedo at (N, 3) unit view vectors (z > 0), interpolated on the grid as
    the table is (slicecap.interpolation), as the page's shader does."""
    directions = to_directions_deg(to_view)
    indices, weights = direction_taps(directions[..., 0], directions[..., 1])
    return np.einsum("nk,nkc->nc", weights, albedo[indices])

# The cloth-like sheet (page only): x, y in [-half_width, half_width], z = fold_depth
# sin(fold_frequency x + fold_skew y) + ripple_depth sin(ripple_frequency y); the tangent is dP/dx.
CLOTH = {
    "half_width": 1.05,
    "fold_depth": 0.2,
    "fold_frequency": 3.5,
    "fold_skew": 0.8,
    "ripple_depth": 0.05,
    "ripple_frequency": 5.0,
}


def page_constants() -> dict:
    """The numbers the page's script takes from its data (viewer_page.js)."""
    return {
        "camera_distance": CAMERA_DISTANCE,
        "fov_deg": FOV_DEG,
        "light_distance": LIGHT_DISTANCE,
        "light_intensity": LIGHT_INTENSITY,
        "defaults": dict(DEFAULTS),
        "cloth": dict(CLOTH),
    }
