"""The material viewer's textured plane (docs/material-viewer.md, "SVBRDF maps"): the maps of
`slicecap fit BTF_DIR -o MAPS_DIR` on a square in the xy plane, shaded per texel with the fit
model under the viewer's point light and constant environment (slicecap.viewer_scene), and its
numpy reference rendering, the picture the page's WebGL plane is checked against.

Plane: x, y in [-HALF_WIDTH, HALF_WIDTH], z = 0, normal +z, tangent +x (the texture's azimuth-0
axis), bitangent +y, as MAPS_DIR/material.gltf's plane: texture row 0 at the top edge (+y),
column 0 at the left (-x). Seen from below, the normal and bitangent flip (as the cloth's back).

normal.png tilts a texel's shading normal (svbrdf_maps.shading_normals, in the texel's frame);
its tangent frame is then the fit's (lib/fit tilted_lobe.hpp tiltedFrame): the anisotropy
direction, an azimuth in the untilted plane, projected onto the plane normal to the tilted
normal, and the bitangent n' x t'. The light's cosine is n'.l (glTF's convention, the fit's
model); nothing direct where the light is behind the plane or the tilted surface. A texel whose
normal bytes are 128, 128 is not tilted and takes the untilted path, bit for bit.
"""

import dataclasses

import numpy as np

from slicecap import albedo_table, viewer_scene
from slicecap.albedo_table import AlbedoTable
from slicecap.svbrdf_maps import (
    SvbrdfMaps,
    decode_parameters,
    shading_normals,
    texel_materials,
    tilted,
)

HALF_WIDTH = 1.0
# Texels the mask says were not fitted: drawn flat in this sRGB colour, not shaded.
MARKER_SRGB8 = (255, 0, 255)
# The page carries the maps as n x n textures and one albedo table (slicecap.albedo_table) of
# 84 x 153 texels, far below OpenGL ES 3.0's promised 2048 a side; writing takes seconds, not
# minutes. 128 = slicecap fit's default, the largest checked in Chromium
# (docs/results/2026-12-02-material-viewer.md); larger sizes were not measured.
MAX_RESOLUTION = 128


def environment_albedo(maps: SvbrdfMaps, table: AlbedoTable, texel: np.ndarray,
                       to_view: np.ndarray, tangent_rad: np.ndarray | None = None) -> np.ndarray:
    """(N, 3) directional albedo of the texels (N,) (row-major indices) at unit views (N, 3) in
    the texel's frame: diffuse x K + f0 x A + (f90 - f0) x B with A, B looked up in the table,
    as the shader's mapsAlbedo. tangent_rad (N,): the tangent's azimuth in that frame, by
    default the maps' (a tilted frame's is 0: its x is the anisotropy direction)."""
    p = decode_parameters(maps)
    shape = maps.images["anisotropy.png"].reshape(-1, 3)[texel].astype(np.float64) / 255.0
    roughness = maps.images["metallic_roughness.png"][..., 1].reshape(-1)[texel] / 255.0
    if tangent_rad is None:
        tangent_rad = np.radians(p["tangent_deg"].reshape(-1)[texel])
    lobe = albedo_table.lookup(table, roughness, shape[:, 2], tangent_rad, to_view)
    f0 = p["specular_f0"].reshape(-1, 3)[texel]
    f90 = p["specular_f90"].reshape(-1)[texel][:, None]
    return (p["diffuse_albedo"].reshape(-1, 3)[texel] * table.diffuse_weight
            + f0 * lobe[:, 0:1] + (f90 - f0) * lobe[:, 1:2])


def texel_index(x: np.ndarray, y: np.ndarray, resolution: int) -> np.ndarray:
    """Row-major texel index at plane points (x, y), as the shader's texelOf."""
    column = np.clip(np.floor((x + HALF_WIDTH) / (2 * HALF_WIDTH) * resolution), 0, resolution - 1)
    row = np.clip(np.floor((HALF_WIDTH - y) / (2 * HALF_WIDTH) * resolution), 0, resolution - 1)
    return (row * resolution + column).astype(np.int64)


def tilted_frames(maps: SvbrdfMaps) -> np.ndarray:
    """(n, n, 3, 3) each texel's tilted frame, rows t', b', n' in its untilted frame (x =
    tangent +x, y = bitangent, z = normal): n' from normal.png, t' the anisotropy direction
    (cos, sin, 0) projected onto the plane normal to n', b' = n' x t' (as the shader's main)."""
    normal = shading_normals(maps)
    angle = np.radians(decode_parameters(maps)["tangent_deg"])
    direction = np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], axis=-1)
    tangent = direction - np.sum(direction * normal, axis=-1, keepdims=True) * normal
    tangent /= np.linalg.norm(tangent, axis=-1, keepdims=True)
    bitangent = np.cross(normal, tangent)
    return np.stack([tangent, bitangent, normal], axis=-2)


def render_plane_point_light(
    maps: SvbrdfMaps, table: AlbedoTable, size: int, light_az_deg: float,
    light_el_deg: float, yaw_deg: float, pitch_deg: float, env: float, normal_map: bool = True,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The plane under the viewer's light and environment, ray-cast in numpy: (size, size, 3)
    linear radiance (row 0 at the top), the (size, size) plane mask and the (size, size) texel
    index (-1 off the plane); a texel not fitted has radiance 0 (display_plane marks it).
    `table` is albedo_table.build_table()'s (as the page carries it). normal_map False: every
    texel untilted, normal.png ignored (the picture before the viewer read normal.png)."""
    materials = [m for row in texel_materials(maps) for m in row]
    origin, rays = viewer_scene.camera_rays(size, yaw_deg, pitch_deg)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = -origin[2] / rays[..., 2]
    point = origin + np.nan_to_num(t, nan=-1.0, posinf=-1.0, neginf=-1.0)[..., None] * rays
    mask = (t > 0) & (np.abs(point[..., 0]) <= HALF_WIDTH) & (np.abs(point[..., 1]) <= HALF_WIDTH)
    point = point[mask]
    side = np.where(origin[2] >= 0.0, 1.0, -1.0)  # the back of the plane: normal flipped
    light = viewer_scene.LIGHT_DISTANCE * viewer_scene.orbit_direction(light_az_deg, light_el_deg)
    to_light = light - point
    distance2 = np.sum(to_light * to_light, axis=-1)
    to_light /= np.sqrt(distance2)[:, None]
    frame = np.array([[1.0, 0.0, 0.0], [0.0, side, 0.0], [0.0, 0.0, side]])
    to_light_local = to_light @ frame.T
    to_view_local = -rays[mask] @ frame.T
    to_view_local[:, 2] = np.maximum(to_view_local[:, 2], 1e-4)
    to_view_local /= np.linalg.norm(to_view_local, axis=-1, keepdims=True)
    texel = texel_index(point[:, 0], point[:, 1], maps.resolution)
    fitted = maps.fitted.reshape(-1)[texel]
    radiance = np.zeros((len(point), 3))
    tilt = fitted & tilted(maps).reshape(-1)[texel] if normal_map else np.zeros_like(fitted)
    flat = fitted & ~tilt
    radiance[flat] = env * environment_albedo(maps, table, texel[flat], to_view_local[flat])
    # Tilted texels: light and view in the texel's tilted frame; the view clamped above its
    # horizon as the untilted one above the plane's.
    frames = tilted_frames(maps).reshape(-1, 3, 3)[texel[tilt]]
    light_tilted = np.einsum("nij,nj->ni", frames, to_light_local[tilt])
    view_tilted = np.einsum("nij,nj->ni", frames, -rays[mask][tilt] @ frame.T)
    view_tilted[:, 2] = np.maximum(view_tilted[:, 2], 1e-4)
    view_tilted /= np.linalg.norm(view_tilted, axis=-1, keepdims=True)
    radiance[tilt] = env * environment_albedo(maps, table, texel[tilt], view_tilted,
                                              np.zeros(np.count_nonzero(tilt)))
    tilt_index = np.flatnonzero(tilt)
    for index in np.unique(texel[fitted]):
        material = materials[index]
        if material is None:  # not reached: the mask and texel_materials agree
            continue
        here = texel == index
        if tilt[here].any():  # tilt is per texel: all of `here` or none
            rows = texel[tilt_index] == index
            lit_rows = rows & (light_tilted[:, 2] > 0.0) & (to_light_local[tilt_index, 2] > 0.0)
            value = dataclasses.replace(material, tangent_deg=0.0).evaluate(
                light_tilted[lit_rows], view_tilted[lit_rows])
            at = tilt_index[lit_rows]
            radiance[at] += value * (
                light_tilted[lit_rows, 2] * viewer_scene.LIGHT_INTENSITY / distance2[at])[:, None]
            continue
        lit = here & (to_light_local[:, 2] > 0.0)
        value = material.evaluate(to_light_local[lit], to_view_local[lit])
        radiance[lit] += value * (
            to_light_local[lit, 2] * viewer_scene.LIGHT_INTENSITY / distance2[lit])[:, None]
    image = np.zeros((size, size, 3))
    image[mask] = radiance
    texels = np.full((size, size), -1, dtype=np.int64)
    texels[mask] = texel
    return image, mask, texels


def display_plane(image: np.ndarray, texels: np.ndarray, maps: SvbrdfMaps,
                  exposure: float) -> np.ndarray:
    """The 8-bit sRGB picture the page shows: radiance x exposure, clipped, sRGB; texels not
    fitted in MARKER_SRGB8; off the plane 0 (the page's background differs: mask it)."""
    from slicecap.image_metrics import to_8bit

    picture = to_8bit(image, 1.0 / exposure)
    unfitted = (texels >= 0) & ~maps.fitted.reshape(-1)[np.maximum(texels, 0)]
    picture[unfitted] = MARKER_SRGB8
    return picture


def interior(texels: np.ndarray) -> np.ndarray:
    """Plane pixels whose 4 neighbours lie on the same texel: where a rasteriser and the ray
    caster cannot pick different texels by a rounding (texel edges and the plane's outline
    are left out of comparisons)."""
    inner = texels >= 0
    inner[1:] &= texels[1:] == texels[:-1]
    inner[:-1] &= texels[:-1] == texels[1:]
    inner[:, 1:] &= texels[:, 1:] == texels[:, :-1]
    inner[:, :-1] &= texels[:, :-1] == texels[:, 1:]
    inner[0, :] = inner[-1, :] = inner[:, 0] = inner[:, -1] = False
    return inner
