"""The SVBRDF plane's environment term (docs/material-viewer.md, "SVBRDF maps"): one table of
the anisotropic GGX lobe's directional albedo, built once per page and looked up per pixel, in
numpy here and in the page's shader (mapsAlbedo), instead of integrating every texel.

With Schlick's Fresnel the fit model's directional albedo splits into terms linear in the
texel's colours: diffuse x K + f0 x A + (f90 - f0) x B, where K is the cos-weighted integral of
1/pi and A, B the integrals of the GGX lobe with Fresnel weights 1 and (1 - l.h)^5. A and B
depend only on the two decoded roughness bytes (metallic_roughness G, anisotropy B) and the view
direction relative to the tangent (elevation, and azimuth folded into [0, 90] deg: the lobe is
symmetric about its tangent and bitangent). All integrals use viewer_scene.directional_albedo's
quadrature (45 x 90 midpoint cells), so a table node equals that per-texel integration exactly.
"""

import math
from dataclasses import dataclass

import numpy as np

from slicecap import viewer_scene

# Nodes: roughness byte / 255 and anisotropy strength byte / 255 uniform in [0, 1]; the view
# elevation uniform in [0, THETA_MAX_DEG] (clamped above: the grid's last ring is 75 deg); the
# azimuth from the tangent uniform in [0, 90] deg.
ROUGHNESS_NODES = 17
STRENGTH_NODES = 9
THETA_NODES = 12
PHI_NODES = 7
THETA_MAX_DEG = 82.5
MIN_ALPHA = 0.002  # svbrdf_maps.MIN_ALPHA, the fit's bound


@dataclass(frozen=True)
class AlbedoTable:
    """values: (ROUGHNESS_NODES * STRENGTH_NODES, THETA_NODES * PHI_NODES, 2) float32 = (A, B);
    row = roughness node * STRENGTH_NODES + strength node, column = theta node * PHI_NODES +
    phi node: the page's RG float texture as laid out. diffuse_weight: K."""

    values: np.ndarray
    diffuse_weight: float


def _alphas(roughness: float, strength: float) -> tuple[float, float]:
    """(alpha_t, alpha_b) as svbrdf_maps.decode_parameters and the shader's loadTexel."""
    alpha_b = max(roughness * roughness, MIN_ALPHA)
    return max(alpha_b + (1.0 - alpha_b) * strength * strength, MIN_ALPHA), alpha_b


def _quadrature() -> tuple[np.ndarray, np.ndarray]:
    """The light directions (L, 3) and weights (L,) of viewer_scene.directional_albedo."""
    steps_t, steps_p = viewer_scene.ALBEDO_STEPS
    theta = (np.arange(steps_t) + 0.5) * (math.pi / 2) / steps_t
    phi = (np.arange(steps_p) + 0.5) * (2 * math.pi) / steps_p
    theta, phi = np.meshgrid(theta, phi, indexing="ij")
    lights = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)],
                      axis=-1).reshape(-1, 3)
    cell = (math.pi / 2 / steps_t) * (2 * math.pi / steps_p)
    return lights, (np.cos(theta) * np.sin(theta)).reshape(-1) * cell


def lobe_integrals(alpha_t: float, alpha_b: float, views: np.ndarray) -> np.ndarray:
    """(V, 2): A and B of the GGX lobe (tangent +x) at (V, 3) unit views (z > 0), integrated as
    viewer_scene.directional_albedo integrates a whole BRDF (fitted_material's GGX terms)."""
    lights, weights = _quadrature()
    at2, ab2 = alpha_t * alpha_t, alpha_b * alpha_b

    def smith_lambda(w: np.ndarray) -> np.ndarray:
        return (np.sqrt(1.0 + (at2 * w[..., 0] ** 2 + ab2 * w[..., 1] ** 2) / w[..., 2] ** 2)
                - 1.0) / 2.0

    light = lights[None, :, :]
    view = views[:, None, :]
    half = light + view
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    s = half[..., 0] ** 2 / at2 + half[..., 1] ** 2 / ab2 + half[..., 2] ** 2
    distribution = 1.0 / (math.pi * alpha_t * alpha_b * s * s)
    lobe = distribution / ((1.0 + smith_lambda(light) + smith_lambda(view))
                           * (4.0 * light[..., 2] * view[..., 2]))
    fresnel_weight = (1.0 - np.clip(np.sum(light * half, axis=-1), 0.0, 1.0)) ** 5
    return np.stack([lobe @ weights, (lobe * fresnel_weight) @ weights], axis=-1)


def node_views() -> np.ndarray:
    """(THETA_NODES * PHI_NODES, 3) unit views of the table's columns, tangent +x."""
    theta = np.radians(np.linspace(0.0, THETA_MAX_DEG, THETA_NODES))[:, None]
    phi = np.radians(np.linspace(0.0, 90.0, PHI_NODES))[None, :]
    views = np.stack(np.broadcast_arrays(np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi),
                                         np.cos(theta)), axis=-1)
    return views.reshape(-1, 3)


def build_table() -> AlbedoTable:
    """The table (ROUGHNESS_NODES x STRENGTH_NODES lobes at 84 views each: ~1 s of numpy)."""
    views = node_views()
    rows = []
    for roughness in np.linspace(0.0, 1.0, ROUGHNESS_NODES):
        for strength in np.linspace(0.0, 1.0, STRENGTH_NODES):
            alpha_t, alpha_b = _alphas(float(roughness), float(strength))
            rows.append(lobe_integrals(alpha_t, alpha_b, views))
    _, weights = _quadrature()
    return AlbedoTable(np.asarray(rows, dtype=np.float32),
                       float(weights.sum()) / math.pi)


def _axis(value: np.ndarray, nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Lower node index and weight of the upper node for values in [0, 1] on uniform nodes."""
    x = np.clip(value, 0.0, 1.0) * (nodes - 1)
    index = np.minimum(np.floor(x), nodes - 2)
    return index.astype(np.int64), x - index


def lookup(table: AlbedoTable, roughness: np.ndarray, strength: np.ndarray, tangent_rad:
           np.ndarray, to_view: np.ndarray) -> np.ndarray:
    """(N, 2): A and B at N pixels, multilinear in the four node axes, as the shader's
    mapsAlbedo: roughness and strength bytes / 255 (N,), the tangent (N,) and unit views in the
    plane's frame (N, 3), z > 0."""
    cos_t, sin_t = np.cos(tangent_rad), np.sin(tangent_rad)
    vx = to_view[:, 0] * cos_t + to_view[:, 1] * sin_t
    vy = -to_view[:, 0] * sin_t + to_view[:, 1] * cos_t
    theta_deg = np.degrees(np.arccos(np.clip(to_view[:, 2], -1.0, 1.0)))
    phi_deg = np.degrees(np.arctan2(np.abs(vy), np.maximum(np.abs(vx), 1e-9)))
    axes = [_axis(roughness, ROUGHNESS_NODES), _axis(strength, STRENGTH_NODES),
            _axis(theta_deg / THETA_MAX_DEG, THETA_NODES), _axis(phi_deg / 90.0, PHI_NODES)]
    result = np.zeros((len(to_view), 2))
    for corner in range(16):
        bits = [(corner >> k) & 1 for k in range(4)]
        weight = np.ones(len(to_view))
        at = []
        for (index, upper), bit in zip(axes, bits, strict=True):
            weight = weight * (upper if bit else 1.0 - upper)
            at.append(index + bit)
        row = at[0] * STRENGTH_NODES + at[1]
        column = at[2] * PHI_NODES + at[3]
        result += weight[:, None] * table.values[row, column]
    return result
