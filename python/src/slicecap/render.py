"""slicecap-render (or python -m slicecap.render) MATERIAL.exr [--reference REF.exr] -o OUT.png

Renders a captured material (and a reference, when given) on a sphere and a cylinder, each under
a few point lights and under one environment map, through the Mitsuba 3 BSDF `slicecap`, and
writes one picture: a row per material, a row of differences (x2) when there is a reference, and
under each column the dE and PSNR of the material's rendering against the reference's (the
paper's 8-bit metrics, slicecap.image_metrics). Exit codes: 0 success, 1 failure (a message
naming the input), 2 bad usage (e.g. an output that is an input).
"""

import argparse
import os
import sys
import time
from collections.abc import Sequence
from types import ModuleType

import numpy as np

from slicecap import viewer_scene
from slicecap.abrdf import Abrdf
from slicecap.abrdf_exr import SlicecapFileError
from slicecap.bitmap_font import GLYPH_HEIGHT, GLYPH_WIDTH, draw_text
from slicecap.grid import Brdf
from slicecap.image_metrics import compare_images, exposure_of, srgb_encode
from slicecap.materials import load_material
from slicecap.paths import StrPath, same_file
from slicecap.png import write_png
from slicecap.scenes import LIGHTINGS, SHAPES, object_mask, scene_dict

COLUMNS = [(shape, lighting) for shape in SHAPES for lighting in LIGHTINGS]
_TEXT_SCALE = 2
DIFFERENCE_GAIN = 2.0
_LINE = (GLYPH_HEIGHT + 3) * _TEXT_SCALE
_MARGIN = 8
MAX_SEED = 2**32 - 1
# A picture per column: (shape, lighting) -> (size, size, 3) linear RGB.
Images = dict[tuple[str, str], np.ndarray]
# The usage names what started it: the console script, or python -m (then this module is __main__).
PROG = "python -m slicecap.render" if __name__ == "__main__" else "slicecap-render"


def _parse(argv: Sequence[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Render a slicecap ABRDF EXR on a sphere and a cylinder under point lights "
        "and an environment map, beside a reference with dE and PSNR.",
    )
    parser.add_argument("material", help="the ABRDF EXR to render")
    parser.add_argument("--reference", help="an ABRDF EXR to render beside it and compare with")
    parser.add_argument("-o", "--output", required=True, help="the picture to write (.png)")
    parser.add_argument("--size", type=int, default=256, help="pixels per rendering (default 256)")
    parser.add_argument("--spp", type=int, default=64, help="samples per pixel (default 64)")
    parser.add_argument(
        "--seed", type=int, default=0, help=f"sampler seed, 0..{MAX_SEED} (default 0)"
    )
    parser.add_argument(
        "--variant",
        default="llvm_ad_rgb",
        help="Mitsuba variant (default llvm_ad_rgb; scalar_rgb works, slowly)",
    )
    return parser.parse_args(argv)


def _set_variant(variant: str) -> ModuleType:
    try:
        import mitsuba as mi
    except ImportError as e:
        raise RuntimeError("mitsuba is not installed: pip install mitsuba (see the README)") from e
    try:
        mi.set_variant(variant)
    except (ImportError, AttributeError) as e:
        raise RuntimeError(
            f"Mitsuba variant {variant} is unavailable ({e}); for llvm_ad_rgb install "
            "libLLVM >= 15 (Debian 12: apt-get install libllvm19) and set DRJIT_LIBLLVM_PATH, "
            "or use --variant scalar_rgb"
        ) from e
    import slicecap.mitsuba_bsdf

    slicecap.mitsuba_bsdf.register()
    return mi


def render_material(mi: ModuleType, path: StrPath, size: int, spp: int, seed: int) -> Images:
    """{(shape, lighting): (size, size, 3) linear rendering} of one EXR."""
    bsdf = {"type": "slicecap", "filename": os.fspath(path)}
    images: Images = {}
    for shape, lighting in COLUMNS:
        scene = mi.load_dict(scene_dict(mi, shape, lighting, bsdf, size, spp))
        images[(shape, lighting)] = np.array(mi.render(scene, seed=seed), dtype=np.float64)
    return images


def render_sphere_point_light(
    brdf: Brdf, albedo: np.ndarray, size: int, light_az_deg: float, light_el_deg: float,
    yaw_deg: float, pitch_deg: float, env: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The unit sphere under the material viewer's point light and constant environment
    (slicecap.viewer_scene, docs/material-viewer.md), ray-cast in numpy with no sampling noise:
    the picture the page's WebGL rendering is checked against (scripts/consumer-check).
    `brdf(to_light, to_view)` maps (N, 3) unit vectors in the surface frame to (N, 3) RGB in 1/sr;
    `albedo` is its (81, 3) directional albedo (viewer_scene.directional_albedo). Returns the
    (size, size, 3) linear radiance (row 0 at the top) and the (size, size) mask of sphere pixels.
    """
    origin, rays = viewer_scene.camera_rays(size, yaw_deg, pitch_deg)
    # |o + t r| = 1: t^2 + 2 (o.r) t + |o|^2 - 1 = 0, the nearer root.
    b = rays @ origin
    discriminant = b * b - (origin @ origin - 1.0)
    mask = discriminant > 0.0
    t = -b[mask] - np.sqrt(discriminant[mask])
    point = origin + t[:, None] * rays[mask]
    normal = point / np.linalg.norm(point, axis=-1, keepdims=True)
    tangent, bitangent = viewer_scene.sphere_frame(normal)

    def to_local(w: np.ndarray) -> np.ndarray:
        return np.stack(
            [np.sum(w * tangent, -1), np.sum(w * bitangent, -1), np.sum(w * normal, -1)], -1
        )

    light = viewer_scene.LIGHT_DISTANCE * viewer_scene.orbit_direction(light_az_deg, light_el_deg)
    to_light = light - point
    distance2 = np.sum(to_light * to_light, axis=-1)
    to_light_local = to_local(to_light / np.sqrt(distance2)[:, None])
    to_view_local = to_local(-rays[mask])
    # Grazing views (the silhouette) are clamped just above the surface, as the shader does.
    to_view_local[:, 2] = np.maximum(to_view_local[:, 2], 1e-4)
    to_view_local /= np.linalg.norm(to_view_local, axis=-1, keepdims=True)
    lit = to_light_local[:, 2] > 0.0
    radiance = env * viewer_scene.albedo_at(albedo, to_view_local)
    value = brdf(to_light_local[lit], to_view_local[lit])
    radiance[lit] += value * (
        to_light_local[lit, 2] * viewer_scene.LIGHT_INTENSITY / distance2[lit]
    )[:, None]
    image = np.zeros((size, size, 3))
    image[mask] = radiance
    return image, mask


def _display(image: np.ndarray, exposure: float) -> np.ndarray:
    return np.floor(srgb_encode(np.clip(image / exposure, 0.0, 1.0)) * 255 + 0.5).astype(np.uint8)


def _draw_fitting(
    canvas: np.ndarray, text: str, row: int, column: int, width: int, colour: tuple[int, int, int]
) -> None:
    """Text at the larger scale when it fits in `width` pixels, else at the smaller."""
    scale = _TEXT_SCALE if len(text) * (GLYPH_WIDTH + 1) * _TEXT_SCALE <= width else 1
    draw_text(canvas, text, row, column, colour=colour, scale=scale)


def compose(
    rows: list[tuple[str, Images]],
    exposures: dict[tuple[str, str], float],
    captions: dict[tuple[str, str], list[str]],
    size: int,
) -> np.ndarray:
    """The picture: column titles, one row of renderings per (label, images), captions below."""
    title_height = _LINE + _MARGIN
    label_height = _LINE
    caption_height = 2 * _LINE + _MARGIN
    row_height = label_height + size + _MARGIN
    height = title_height + len(rows) * row_height + caption_height
    width = _MARGIN + len(COLUMNS) * (size + _MARGIN)
    canvas = np.full((height, width, 3), 24, dtype=np.uint8)
    for c, (shape, lighting) in enumerate(COLUMNS):
        x = _MARGIN + c * (size + _MARGIN)
        _draw_fitting(canvas, f"{shape}/{lighting}", _MARGIN, x, size, (255, 255, 255))
        for r, (label, images) in enumerate(rows):
            y = title_height + r * row_height
            if c == 0:
                _draw_fitting(canvas, label, y, x, width - x, (200, 200, 120))
            canvas[y + label_height : y + label_height + size, x : x + size] = _display(
                images[(shape, lighting)], exposures[(shape, lighting)]
            )
        y = title_height + len(rows) * row_height
        for k, line in enumerate(captions.get((shape, lighting), [])):
            _draw_fitting(canvas, line, y + k * _LINE, x, size, (150, 220, 150))
    return canvas


def _label(path: StrPath, material: Abrdf) -> str:
    name = material.attributes.get("material") or os.path.splitext(os.path.basename(path))[0]
    return f"{name} ({material.attributes.get('method', '?')})"


def run(argv: Sequence[str]) -> int:
    args = _parse(argv)
    if args.size < 8 or args.spp < 1:
        print("slicecap.render: --size must be >= 8 and --spp >= 1", file=sys.stderr)
        return 2
    if not 0 <= args.seed <= MAX_SEED:
        # Mitsuba takes an unsigned 32-bit seed; anything else failed deep inside mi.render.
        print(f"slicecap.render: --seed must be in 0..{MAX_SEED}", file=sys.stderr)
        return 2
    for role, path in (("material", args.material), ("reference", args.reference)):
        if path and same_file(args.output, path):
            print(
                f"slicecap.render: -o {args.output} is the {role}: it would be overwritten",
                file=sys.stderr,
            )
            return 2
    # Rendering takes seconds to minutes: a folder the picture cannot go to is said first.
    folder = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(folder) or not os.access(folder, os.W_OK | os.X_OK):
        print(
            f"slicecap.render: {args.output}: the folder {folder} does not exist"
            " or is not writable",
            file=sys.stderr,
        )
        return 1
    try:
        material = load_material(args.material)
        reference = load_material(args.reference) if args.reference else None
        mi = _set_variant(args.variant)
        started = time.perf_counter()
        images = render_material(mi, args.material, args.size, args.spp, args.seed)
        rows = [(_label(args.material, material), images)]
        exposures: dict[tuple[str, str], float] = {}
        captions: dict[tuple[str, str], list[str]] = {}
        masks = {shape: object_mask(mi, shape, args.size) for shape in SHAPES}
        if reference is not None:
            reference_images = render_material(mi, args.reference, args.size, args.spp, args.seed)
            rows.append((_label(args.reference, reference), reference_images))
            differences: Images = {}
            for key in COLUMNS:
                mask = masks[key[0]]
                exposures[key] = exposure_of(reference_images[key], mask)
                metrics = compare_images(reference_images[key], images[key], mask)
                captions[key] = [f"dE {metrics.delta_e:.2f}", f"PSNR {metrics.psnr_db:.1f} dB"]
                differences[key] = DIFFERENCE_GAIN * np.abs(images[key] - reference_images[key])
                print(
                    f"{key[0]:8s} {key[1]:6s}  dE {metrics.delta_e:6.2f}  "
                    f"RMSE {metrics.rmse:6.2f}  PSNR {metrics.psnr_db:6.2f} dB"
                )
            rows.append((f"difference x{DIFFERENCE_GAIN:g}", differences))
        else:
            for key in COLUMNS:
                exposures[key] = exposure_of(images[key], masks[key[0]])
        canvas = compose(rows, exposures, captions, args.size)
        write_png(args.output, canvas)
    except (SlicecapFileError, RuntimeError, ValueError) as e:
        print(f"slicecap.render: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        print(f"slicecap.render: {args.output}: {e.strerror}", file=sys.stderr)
        return 1
    print(
        f"wrote {args.output} ({canvas.shape[1]} x {canvas.shape[0]}, "
        f"{time.perf_counter() - started:.1f} s)"
    )
    return 0


def main() -> None:
    sys.exit(run(sys.argv[1:]))


if __name__ == "__main__":
    main()
