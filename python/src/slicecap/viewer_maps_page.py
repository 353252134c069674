"""The material viewer's page for SVBRDF maps (python -m slicecap.viewer --maps MAPS_DIR,
docs/material-viewer.md): the maps of `slicecap fit BTF_DIR -o MAPS_DIR` on a plane
(slicecap.viewer_plane), in the same page, script and shader as the table viewer (viewer_page.*).
"""

import base64
import html
import os

import numpy as np

from slicecap import albedo_table, viewer_plane, viewer_scene
from slicecap.abrdf_exr import SlicecapFileError
from slicecap.albedo_table import AlbedoTable
from slicecap.image_metrics import EXPOSURE_PERCENTILE
from slicecap.paths import StrPath
from slicecap.svbrdf_maps import MAP_FILES, NORMAL_MAP, SvbrdfMaps, read_maps, tilted
from slicecap.viewer_template import fill_template

_EXPOSURE_PROBE_SIZE = 96


def packed_textures(maps: SvbrdfMaps) -> dict[str, np.ndarray]:
    """The (n, n, 4) uint8 textures the shader's loadTexel reads: base colour + mask, specular
    (RGB + F90), anisotropy RGB + roughness (metallic_roughness G); and (n, n, 2) normal.png's
    R, G (the shading normal's x, y; B is the z they give)."""
    images = maps.images
    return {
        "base": np.concatenate([images["base_color.png"], images["mask.png"]], axis=-1),
        "specular": images["specular.png"],
        "shape": np.concatenate(
            [images["anisotropy.png"], images["metallic_roughness.png"][..., 1:2]], axis=-1),
        "normal": images[NORMAL_MAP][..., :2],
    }


def default_exposure(maps: SvbrdfMaps, table: AlbedoTable) -> float:
    """1 / the EXPOSURE_PERCENTILE-th percentile of the fitted texels' radiance under the
    default view (as the table viewer's sphere)."""
    d = viewer_scene.DEFAULTS
    image, _, texels = viewer_plane.render_plane_point_light(
        maps, table, _EXPOSURE_PROBE_SIZE, d["light_az"], d["light_el"], d["yaw"], d["pitch"],
        d["env"])
    fitted = (texels >= 0) & maps.fitted.reshape(-1)[np.maximum(texels, 0)]
    if not np.any(fitted):
        return 1.0
    level = float(np.percentile(image[fitted], EXPOSURE_PERCENTILE))
    return 1.0 / level if level > 0.0 else 1.0


def _side_details(maps: SvbrdfMaps) -> str:
    marker = "rgb({}, {}, {})".format(*viewer_plane.MARKER_SRGB8)
    unfitted = int(np.count_nonzero(~maps.fitted))
    shown = [name for name in (*MAP_FILES, NORMAL_MAP) if name in maps.png_bytes]
    thumbnails = "".join(
        f'<img class="map" title="{name}" alt="{name}" src="data:image/png;base64,'
        f'{base64.b64encode(maps.png_bytes[name]).decode("ascii")}">'
        for name in shown
    )
    tilted_texels = int(np.count_nonzero(tilted(maps) & maps.fitted))
    if maps.normal_note is not None:
        # Shown where the user looks, not only on stdout: the highlights are the untilted ones.
        normals = f'<p class="note">{html.escape(maps.normal_note)}.</p>'
    else:
        normals = (f"<p>normal.png: {tilted_texels} of {maps.resolution ** 2} texels tilted, "
                   "each shaded about its own normal (tangent frame turned onto it).</p>")
    return (
        f"<p>The SVBRDF maps ({maps.resolution} x {maps.resolution} texels, IOR {maps.ior:.4g}) "
        "on a plane, each texel shaded with the fit model (diffuse + anisotropic GGX + Schlick "
        "f0/f90) decoded from the maps; tangent = the texture's x (right), row 0 at the top.</p>"
        f"{normals}"
        f'<p><span class="swatch" style="background: {marker}"></span> texel not fitted '
        f"(mask.png 0): {unfitted} of {maps.resolution ** 2}, drawn flat, not shaded.</p>"
        f"<p>{', '.join(name.removesuffix('.png') for name in shown)}:</p>{thumbnails}"
    )


def build_maps_page(maps_dir: StrPath, panel_size: int) -> str:
    """The page's HTML text for MAPS_DIR. Raises SlicecapFileError naming the file that is
    missing, not a PNG, truncated or of the wrong size (svbrdf_maps.read_maps), or maps.json
    when the maps are larger than viewer_plane.MAX_RESOLUTION."""
    maps = read_maps(maps_dir)
    if maps.resolution > viewer_plane.MAX_RESOLUTION:
        raise SlicecapFileError(
            f"{os.path.join(maps.directory, 'maps.json')}: {maps.resolution} x "
            f"{maps.resolution} texels; the viewer shows maps up to "
            f"{viewer_plane.MAX_RESOLUTION} x {viewer_plane.MAX_RESOLUTION}")
    table = albedo_table.build_table()
    name = os.path.basename(os.path.normpath(maps.directory))

    def encoded(values: np.ndarray, dtype: str) -> str:
        return base64.b64encode(np.ascontiguousarray(values, dtype=dtype).tobytes()).decode()

    textures = packed_textures(maps)
    data = {
        "panel_size": panel_size,
        "scene": viewer_scene.page_constants(),
        "exposure": default_exposure(maps, table),
        "table": None,
        "material": None,
        "maps": {
            "name": name,
            "resolution": maps.resolution,
            "ior_f0": maps.ior_f0,
            "half_width": viewer_plane.HALF_WIDTH,
            "marker": list(viewer_plane.MARKER_SRGB8),
            **{f"{key}_base64": encoded(value, "u1") for key, value in textures.items()},
            "albedo_table": {
                "width": table.values.shape[1], "height": table.values.shape[0],
                "diffuse_weight": table.diffuse_weight,
                "nodes": [albedo_table.ROUGHNESS_NODES, albedo_table.STRENGTH_NODES,
                          albedo_table.THETA_NODES, albedo_table.PHI_NODES],
                "theta_max_deg": albedo_table.THETA_MAX_DEG,
                "base64": encoded(table.values, "<f4"),
            },
        },
    }
    return fill_template({
        # No label over the plane (the side panel's title names it): a label would cover texels
        # the browser check compares.
        "{{LABELS}}": "",
        "{{SIDE_LEFT}}": str(panel_size),
        "{{TITLE}}": html.escape(f"{name} (SVBRDF maps)"),
        "{{SIDE_DETAILS}}": _side_details(maps),
    }, data)
