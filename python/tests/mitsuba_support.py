"""Helpers for the tests that need Mitsuba: variant selection that skips with a clear message,
a tiny sphere scene (z up), an analytic Phong BSDF in Python."""

import numpy as np
import pytest

from slicecap.scenes import sky_image


def use_variant(variant: str):
    """Imports mitsuba, switches to `variant` and registers the plugin; skips when impossible."""
    mi = pytest.importorskip(
        "mitsuba", reason="mitsuba is not installed (requirements-mitsuba.txt)"
    )
    try:
        mi.set_variant(variant)
    except (ImportError, AttributeError) as e:
        pytest.skip(
            f"Mitsuba variant {variant} is unavailable here ({e}); llvm variants need "
            "libLLVM >= 15 with DRJIT_LIBLLVM_PATH (scripts/python-test sets it)"
        )
    import slicecap.mitsuba_bsdf

    slicecap.mitsuba_bsdf.register()
    return mi


def sphere_scene(mi, bsdf: dict, size=48, spp=64, seed=0, lights="both"):
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": {
            "type": "perspective",
            "fov": 28,
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[0, -1.5, 4.5], target=[0, 0, 0], up=[0, 0, 1]
            ),
            "film": {"type": "hdrfilm", "width": size, "height": size, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp, "seed": seed},
        },
        "sphere": {"type": "sphere", "bsdf": bsdf},
    }
    if lights in ("both", "points"):
        scene["key"] = {
            "type": "point",
            "position": [3, -3, 4],
            "intensity": {"type": "rgb", "value": 30.0},
        }
        scene["rim"] = {
            "type": "point",
            "position": [-4, 2, 1],
            "intensity": {"type": "rgb", "value": 12.0},
        }
    if lights in ("both", "envmap"):
        scene["sky"] = {"type": "envmap", "bitmap": mi.Bitmap(sky_image(64, 32))}
    return mi.load_dict(scene)


def render(mi, scene, seed=0) -> np.ndarray:
    return np.array(mi.render(scene, seed=seed), dtype=np.float64)


def phong(kd, ks, exponent):
    """The modified (energy-normalised) Phong BRDF as a numpy function of unit vectors."""
    kd = np.asarray(kd, dtype=np.float64)
    ks = np.asarray(ks, dtype=np.float64)

    def brdf(to_light, to_view):
        mirrored = to_light * np.array([-1.0, -1.0, 1.0])
        cos_alpha = np.clip(np.sum(mirrored * to_view, axis=-1), 0.0, 1.0)
        lobe = (exponent + 2) / (2 * np.pi) * cos_alpha**exponent
        return kd / np.pi + ks * lobe[..., None]

    return brdf


def analytic_phong_bsdf_class(mi, kd, ks, exponent):
    """A Python Mitsuba BSDF evaluating the same Phong formula directly (cosine sampling)."""
    import drjit as dr

    class AnalyticPhong(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [flags]
            self.m_flags = flags

        def eval(self, ctx, si, wo, active=True):
            active = active & (si.wi.z > 0) & (wo.z > 0)
            mirrored = mi.Vector3f(-wo.x, -wo.y, wo.z)
            cos_alpha = dr.clip(dr.dot(mirrored, si.wi), 0.0, 1.0)
            lobe = (exponent + 2) / (2 * dr.pi) * dr.power(cos_alpha, exponent)
            value = mi.Color3f(*kd) * dr.inv_pi + mi.Color3f(*ks) * lobe
            return dr.select(active, value * wo.z, 0.0)

        def pdf(self, ctx, si, wo, active=True):
            return dr.select(active & (si.wi.z > 0) & (wo.z > 0), wo.z * dr.inv_pi, 0.0)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = mi.warp.square_to_cosine_hemisphere(sample2)
            bs.pdf = self.pdf(ctx, si, bs.wo, active)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            value = self.eval(ctx, si, bs.wo, active)
            return bs, dr.select(bs.pdf > 0, value / dr.maximum(bs.pdf, 1e-20), 0.0)

        def traverse(self, callback):
            pass

        def to_string(self):
            return "AnalyticPhong"

    return AnalyticPhong
