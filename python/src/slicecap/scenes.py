"""The renderer's scenes: a sphere and a cylinder (the paper's Figs. 18-20), each under a few
point lights or under one environment map, as Mitsuba 3 scene dictionaries (y is up)."""

from types import ModuleType

import numpy as np

SHAPES = ("sphere", "cylinder")
LIGHTINGS = ("points", "envmap")
_CAMERA = {"sphere": ([0.0, 1.2, 4.6], 30.0), "cylinder": ([0.0, 0.0, 4.8], 30.0)}
_POINT_LIGHTS = (
    ([3.0, 4.0, 4.0], 40.0),  # key, above right
    ([-4.0, 1.0, 2.0], 14.0),  # fill, left
    ([1.0, 2.0, -4.0], 30.0),  # rim, behind
)


def sky_image(width: int = 128, height: int = 64) -> np.ndarray:
    """A procedural latitude-longitude environment (y up): a sky graded to white at the horizon,
    a warm small sun, a dark ground with a lighter patch. No file to download or ship."""
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    elevation = (0.5 - v) * np.pi
    sky = np.stack(
        [0.35 + 0.65 * np.cos(elevation), 0.55 + 0.45 * np.cos(elevation), np.ones_like(v)], axis=-1
    )
    ground = np.tile([0.12, 0.10, 0.08], (height, 1))
    rows = np.where((v < 0.5)[:, None], sky, ground)
    image = np.repeat(rows[:, None, :], width, axis=1)
    patch = (v[:, None] > 0.62) & (v[:, None] < 0.75) & (np.abs(u[None, :] - 0.75) < 0.08)
    image[patch] = (0.45, 0.40, 0.30)
    sun = (np.abs(u[None, :] - 0.35) < 0.02) & (np.abs(v[:, None] - 0.22) < 0.03)
    image[sun] = (60.0, 54.0, 40.0)
    return image.astype(np.float32)


def _shape(shape: str, bsdf: dict) -> dict:
    if shape == "sphere":
        return {"type": "sphere", "radius": 1.0, "bsdf": bsdf}
    if shape == "cylinder":
        return {
            "type": "cylinder",
            "p0": [0, -1.0, 0],
            "p1": [0, 1.0, 0],
            "radius": 0.75,
            "bsdf": bsdf,
        }
    raise ValueError(f"unknown shape {shape!r} (expected one of {SHAPES})")


def scene_dict(
    mi: ModuleType,
    shape: str,
    lighting: str,
    bsdf: dict,
    size: int,
    spp: int,
    integrator: dict | None = None,
) -> dict:
    """One scene: `shape` with `bsdf`, lit by `lighting`, seen by a size x size camera."""
    origin, fov = _CAMERA[shape]
    scene = {
        "type": "scene",
        "integrator": integrator or {"type": "path", "max_depth": 3},
        "sensor": {
            "type": "perspective",
            "fov": fov,
            "to_world": mi.ScalarTransform4f().look_at(
                origin=origin, target=[0, 0, 0], up=[0, 1, 0]
            ),
            "film": {"type": "hdrfilm", "width": size, "height": size, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "object": _shape(shape, bsdf),
    }
    if lighting == "points":
        for k, (position, intensity) in enumerate(_POINT_LIGHTS):
            scene[f"light{k}"] = {
                "type": "point",
                "position": position,
                "intensity": {"type": "rgb", "value": intensity},
            }
    elif lighting == "envmap":
        scene["sky"] = {"type": "envmap", "bitmap": mi.Bitmap(sky_image())}
    else:
        raise ValueError(f"unknown lighting {lighting!r} (expected one of {LIGHTINGS})")
    return scene


def object_mask(mi: ModuleType, shape: str, size: int) -> np.ndarray:
    """(size, size) True where the camera sees the object (from a depth AOV)."""
    integrator = {"type": "aov", "aovs": "depth:depth"}
    scene = mi.load_dict(scene_dict(mi, shape, "points", {"type": "diffuse"}, size, 4, integrator))
    depth = np.array(mi.render(scene, spp=4))[..., 0]
    return depth > 0
