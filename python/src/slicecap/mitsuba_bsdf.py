"""The Mitsuba 3 BSDF `slicecap`: a captured ABRDF on any shape, in every Mitsuba variant.

    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    import slicecap.mitsuba_bsdf
    slicecap.mitsuba_bsdf.register()
    bsdf = mi.load_dict({"type": "slicecap", "filename": "satin.exr"})

The local frame is Mitsuba's shading frame: z = normal, x = the shape's tangent (dp/du), azimuths
counter-clockwise from x, as the Bonn grid's (docs/method.md §1.2). One-sided like `diffuse`. `eval`
interpolates the table exactly as slicecap.evaluate does (16 table entries per call, vectorised
with Dr.Jit gathers); `sample` draws from the tabulated mixture of slicecap.sampling, mixed with a
cosine-weighted share.

The BSDF `slicecap_analytic` renders the exact model behind a table of `slicecap generate` (a
built-in material or a model specification), in the same frame and orientation, evaluated by
slicecap.analytic_models' formulas in Dr.Jit; it samples cosine-weighted:

    truth = mi.load_dict({"type": "slicecap_analytic", "filename": "satin-blue-45.exr"})
"""

from collections.abc import Sequence
from typing import Any

import drjit as dr
import mitsuba as mi
import numpy as np

from slicecap import sampling
from slicecap.analytic_models import model_of_table, parse_model
from slicecap.materials import load_material

PLUGIN_NAME = "slicecap"
ANALYTIC_PLUGIN_NAME = "slicecap_analytic"
_RING_COUNTS = (1, 6, 12, 18, 20, 24)
_RING_FIRST = (0, 1, 7, 19, 37, 57)
_RING_STEP_DEG = 15.0
# Mitsuba and Dr.Jit values (one per lane): Python numbers in scalar variants, JIT arrays in the
# others. The variant is chosen at run time, so no one static type fits: they are typed Any.
DrValue = Any
# A (grid index, weight) tap of a direction.
Tap = tuple[DrValue, DrValue]


def _ring_property(ring: DrValue, values: tuple[int, ...]) -> DrValue:
    """values[ring] for a per-lane ring number, by selects (works in scalar and JIT variants)."""
    result = mi.UInt32(values[0])
    for r in range(1, len(values)):
        result = dr.select(ring == r, mi.UInt32(values[r]), result)
    return result


def _azimuth_taps(ring: DrValue, phi_deg: DrValue) -> tuple[Tap, Tap]:
    """Two (index, weight) taps on each lane's ring: periodic linear in azimuth."""
    count = _ring_property(ring, _RING_COUNTS)
    first = _ring_property(ring, _RING_FIRST)
    position = phi_deg * mi.Float(count) / 360.0
    lower = mi.UInt32(dr.floor(position))
    fraction = dr.clip(position - mi.Float(lower), 0.0, 1.0)
    lower = dr.select(lower >= count, lower - count, lower)
    upper = dr.select(lower + 1 >= count, 0, lower + 1)
    return (first + lower, 1.0 - fraction), (first + upper, fraction)


def direction_taps(v: DrValue) -> list[Tap]:
    """Four (grid index, weight) taps of a local unit vector (the rule of slicecap.interpolation:
    two rings around the elevation, the 75 deg ring above 75)."""
    theta_deg = dr.rad2deg(dr.safe_acos(v.z))
    phi_deg = dr.rad2deg(dr.atan2(v.y, v.x))
    phi_deg = dr.select(phi_deg < 0.0, phi_deg + 360.0, phi_deg)
    phi_deg = dr.select(phi_deg >= 360.0, 0.0, phi_deg)
    upper = mi.UInt32(1)
    for ring_theta_deg in (15.0, 30.0, 45.0, 60.0):
        upper = dr.select(theta_deg > ring_theta_deg, upper + 1, upper)
    lower = upper - 1
    t = dr.clip((theta_deg - _RING_STEP_DEG * mi.Float(lower)) / _RING_STEP_DEG, 0.0, 1.0)
    taps = []
    for ring, ring_weight in ((lower, 1.0 - t), (upper, t)):
        for index, weight in _azimuth_taps(ring, phi_deg):
            taps.append((index, weight * ring_weight))
    return taps


class _Tables:
    """The table and the sampling histograms as flat arrays of the current variant, with gathers
    that work in scalar variants too (where Dr.Jit has no gather of Python floats)."""

    def __init__(self, values: np.ndarray) -> None:
        self.jit = dr.is_jit_v(mi.Float)
        self.brdf = self._array(values.reshape(-1))
        radiance = sampling.build_sampling_tables(values, known_side="view")
        importance = sampling.build_sampling_tables(values, known_side="light")
        self.pmf = {
            side: self._array(t.pmf.reshape(-1))
            for side, t in (("view", radiance), ("light", importance))
        }
        self.cdf = {
            side: self._array(t.cdf.reshape(-1))
            for side, t in (("view", radiance), ("light", importance))
        }
        self.bins = sampling.COS_BINS * sampling.PHI_BINS
        self.bin_solid_angle_sr = radiance.bin_solid_angle_sr

    def _array(self, values: np.ndarray) -> DrValue:
        values = np.ascontiguousarray(values, dtype=np.float32)
        return mi.Float(values) if self.jit else values

    def gather(self, array: DrValue, index: DrValue, active: DrValue = True) -> DrValue:
        if self.jit:
            return dr.gather(mi.Float, array, index, active)
        return float(array[index]) if active else 0.0

    def brdf_rgb(self, index: DrValue, active: DrValue = True) -> DrValue:
        if self.jit:
            return dr.gather(mi.Color3f, self.brdf, index, active)
        if not active:
            return mi.Color3f(0.0)
        return mi.Color3f(*(float(x) for x in self.brdf[3 * index : 3 * index + 3]))


def _bin_of(v: DrValue) -> DrValue:
    """Flat histogram bin of a local direction (slicecap.sampling.bin_of)."""
    a = dr.clip(mi.Int32(dr.floor(v.z * sampling.COS_BINS)), 0, sampling.COS_BINS - 1)
    phi = dr.atan2(v.y, v.x)
    phi = dr.select(phi < 0.0, phi + dr.two_pi, phi)
    b = dr.clip(mi.Int32(dr.floor(phi * (sampling.PHI_BINS / dr.two_pi))), 0, sampling.PHI_BINS - 1)
    return mi.UInt32(a * sampling.PHI_BINS + b)


def _file_resolver() -> DrValue:
    """Mitsuba's file resolver (mi.file_resolver() in recent versions, the thread's before)."""
    resolver = getattr(mi, "file_resolver", None)
    if resolver is not None:
        return resolver()
    return mi.Thread.thread().file_resolver()


def _oriented(ctx: DrValue, wi: DrValue, wo: DrValue) -> tuple[DrValue, DrValue, str]:
    """(light, view, known side) for Mitsuba's (wi, wo): from the camera wi is the view. Both
    BSDFs here orient their (light, view) pair by this, in Mitsuba's shading frame (z = normal,
    x = dp/du), the frame of the table's Bonn grid."""
    if ctx.mode == mi.TransportMode.Radiance:
        return wo, wi, "view"
    return wi, wo, "light"


def _active(ctx: DrValue, si: DrValue, wo: DrValue, active: DrValue) -> DrValue:
    """Lanes a one-sided glossy reflection answers: both directions above the surface."""
    enabled = ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
    cos_i = mi.Frame3f.cos_theta(si.wi)
    cos_o = mi.Frame3f.cos_theta(wo)
    return active & enabled & (cos_i > 0.0) & (cos_o > 0.0)


def _make_base_class() -> type:
    class OneSidedGlossyBsdf(mi.BSDF):
        """What both slicecap BSDFs share: one-sided glossy reflection, eval as the subclass's
        `_value(light, view, active)` (RGB BRDF, 1/sr) times cos(wo) in the orientation of
        _oriented, no differentiable parameters."""

        def _value(self, light: DrValue, view: DrValue, active: DrValue) -> DrValue:
            raise NotImplementedError  # each BSDF's own: the table's lookup, the model's formula

        def _set_flags(self) -> None:
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [flags]
            self.m_flags = flags

        def eval(self, ctx: DrValue, si: DrValue, wo: DrValue, active: DrValue = True) -> DrValue:
            active = _active(ctx, si, wo, active)
            light, view, _ = _oriented(ctx, si.wi, wo)
            value = self._value(light, view, active) * mi.Frame3f.cos_theta(wo)
            return dr.select(active, value, mi.Color3f(0.0))

        def eval_pdf(
            self, ctx: DrValue, si: DrValue, wo: DrValue, active: DrValue = True
        ) -> tuple[DrValue, DrValue]:
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def traverse(self, callback: DrValue) -> None:
            pass

        def parameters_changed(self, keys: Sequence[str] | None = None) -> None:
            pass

    return OneSidedGlossyBsdf


def _make_class(base: type) -> type:
    class SlicecapBsdf(base):
        """A slicecap ABRDF EXR (property `filename`) as a one-sided glossy BSDF."""

        def __init__(self, props: DrValue) -> None:
            mi.BSDF.__init__(self, props)
            if "filename" not in props:
                raise ValueError(
                    "slicecap BSDF: the property 'filename' (an ABRDF EXR) is required"
                )
            # As Mitsuba's own plugins: relative to the scene file's folder (which load_file puts
            # on the file resolver), then the resolver's other folders, then as given.
            self.filename = str(_file_resolver().resolve(str(props["filename"])))
            self.material = load_material(self.filename)
            self.tables = _Tables(self.material.values)
            self._set_flags()

        def _value(self, light: DrValue, view: DrValue, active: DrValue) -> DrValue:
            light_taps = direction_taps(light)
            view_taps = direction_taps(view)
            value = mi.Color3f(0.0)
            for light_index, light_weight in light_taps:
                for view_index, view_weight in view_taps:
                    entry = self.tables.brdf_rgb(light_index * 81 + view_index, active)
                    value += entry * (light_weight * view_weight)
            return value

        def _pdf(self, known: DrValue, unknown: DrValue, side: str, active: DrValue) -> DrValue:
            """Density in solid angle of sampling `unknown` (cosine share plus the tap-weighted
            histograms of the known direction)."""
            bin_index = _bin_of(unknown)
            tabulated = mi.Float(0.0)
            for index, weight in direction_taps(known):
                mass = self.tables.gather(
                    self.tables.pmf[side], index * self.tables.bins + bin_index, active
                )
                tabulated += weight * mass
            tabulated /= self.tables.bin_solid_angle_sr
            cosine = dr.maximum(unknown.z, 0.0) * dr.inv_pi
            pdf = sampling.COSINE_SHARE * cosine + (1.0 - sampling.COSINE_SHARE) * tabulated
            return dr.select(active & (unknown.z > 0.0), pdf, 0.0)

        def pdf(self, ctx: DrValue, si: DrValue, wo: DrValue, active: DrValue = True) -> DrValue:
            active = _active(ctx, si, wo, active)
            _, _, side = _oriented(ctx, si.wi, wo)
            return self._pdf(si.wi, wo, side, active)

        def sample(
            self,
            ctx: DrValue,
            si: DrValue,
            sample1: DrValue,
            sample2: DrValue,
            active: DrValue = True,
        ) -> tuple[DrValue, DrValue]:
            _, _, side = _oriented(ctx, si.wi, si.wi)
            active = active & ctx.is_enabled(mi.BSDFFlags.GlossyReflection)
            active = active & (mi.Frame3f.cos_theta(si.wi) > 0.0)
            # Pick one of the known direction's taps by its weight, reusing sample1.
            taps = direction_taps(si.wi)
            chosen_index = mi.UInt32(taps[0][0])
            start = mi.Float(0.0)
            width = mi.Float(taps[0][1])
            running = mi.Float(0.0)
            for index, weight in taps:
                pick = (sample1 >= running) & (sample1 < running + weight)
                chosen_index = dr.select(pick, index, chosen_index)
                start = dr.select(pick, running, start)
                width = dr.select(pick, weight, width)
                running = running + weight
            u = dr.clip((sample1 - start) / dr.maximum(width, 1e-12), 0.0, 0.99999994)
            use_cosine = u < sampling.COSINE_SHARE
            u = dr.select(
                use_cosine,
                u / sampling.COSINE_SHARE,
                (u - sampling.COSINE_SHARE) / (1.0 - sampling.COSINE_SHARE),
            )
            # A histogram bin of the chosen tap by its mass, then a uniform point inside it.
            row = chosen_index * self.tables.bins
            cdf = self.tables.cdf[side]
            bin_index = dr.binary_search(
                0, self.tables.bins - 1, lambda i: self.tables.gather(cdf, row + i, active) <= u
            )
            cos_theta = (mi.Float(bin_index // sampling.PHI_BINS) + sample2.x) / sampling.COS_BINS
            phi = (mi.Float(bin_index % sampling.PHI_BINS) + sample2.y) * (
                dr.two_pi / sampling.PHI_BINS
            )
            sin_theta = dr.safe_sqrt(1.0 - cos_theta * cos_theta)
            tabulated_wo = mi.Vector3f(sin_theta * dr.cos(phi), sin_theta * dr.sin(phi), cos_theta)
            cosine_wo = mi.warp.square_to_cosine_hemisphere(sample2)
            wo = dr.select(use_cosine, cosine_wo, tabulated_wo)

            # DrValue: the stubs type its fields for one variant family (eta a Dr.Jit Float, where
            # scalar variants take a Python float).
            bs: DrValue = dr.zeros(mi.BSDFSample3f)
            bs.wo = wo
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            value, pdf = self.eval_pdf(ctx, si, wo, active)
            bs.pdf = pdf
            active = active & (pdf > 0.0)
            weight = dr.select(active, value / dr.maximum(pdf, 1e-20), mi.Color3f(0.0))
            return bs, weight

        def to_string(self) -> str:
            material = self.material.attributes.get("material", "?")
            return f"SlicecapBSDF[filename={self.filename!r}, material={material!r}]"

    return SlicecapBsdf


def _make_analytic_class(base: type) -> type:
    class SlicecapAnalyticBsdf(base):
        """A slicecap built-in analytic model (slicecap.analytic_models) as a one-sided glossy
        BSDF: property `model`, its description (a line of `slicecap generate --list` after the
        name), or `filename`, a table `slicecap generate` wrote, whose model it reads. The exact
        truth behind such a table, in the table plugin's frame and orientation."""

        def __init__(self, props: DrValue) -> None:
            mi.BSDF.__init__(self, props)
            if ("model" in props) == ("filename" in props):
                raise ValueError(
                    "slicecap_analytic BSDF: give one of the properties 'model' (a model "
                    "description) or 'filename' (a table of `slicecap generate`)"
                )
            if "model" in props:
                self.source = str(props["model"])
                self.model = parse_model(self.source)
            else:
                self.source = str(_file_resolver().resolve(str(props["filename"])))
                self.model = model_of_table(self.source)
            self._set_flags()

        def _value(self, light: DrValue, view: DrValue, active: DrValue) -> DrValue:
            # Lanes below the surface may divide by zero here; eval's select drops them.
            r, g, b = self.model.channels((light.x, light.y, light.z), (view.x, view.y, view.z), dr)
            return mi.Color3f(r, g, b)

        def pdf(self, ctx: DrValue, si: DrValue, wo: DrValue, active: DrValue = True) -> DrValue:
            # Cosine-weighted: unbiased for any of the models, if noisy for narrow lobes under
            # BSDF sampling (a point light is sampled from the light, where this does not count).
            active = _active(ctx, si, wo, active)
            return dr.select(active, mi.Frame3f.cos_theta(wo) * dr.inv_pi, 0.0)

        def sample(
            self,
            ctx: DrValue,
            si: DrValue,
            sample1: DrValue,
            sample2: DrValue,
            active: DrValue = True,
        ) -> tuple[DrValue, DrValue]:
            bs: DrValue = dr.zeros(mi.BSDFSample3f)
            bs.wo = mi.warp.square_to_cosine_hemisphere(sample2)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            value, pdf = self.eval_pdf(ctx, si, bs.wo, active)
            bs.pdf = pdf
            active = active & (pdf > 0.0)
            weight = dr.select(active, value / dr.maximum(pdf, 1e-20), mi.Color3f(0.0))
            return bs, weight

        def to_string(self) -> str:
            return f"SlicecapAnalyticBSDF[{self.model.description!r}]"

    return SlicecapAnalyticBsdf


_registered_variants: set[str] = set()


def register() -> None:
    """Registers the BSDFs `slicecap` (a table) and `slicecap_analytic` (a built-in analytic
    model) for the current Mitsuba variant (call after set_variant).
    Raises RuntimeError for a variant that is not RGB (spectral, monochrome, polarized): the
    table is RGB, and there its lookups failed only when rendering, with std::bad_cast."""
    variant = mi.variant()
    if variant is None:
        raise RuntimeError("slicecap.mitsuba_bsdf.register: call mitsuba.set_variant() first")
    if not mi.is_rgb or mi.is_polarized:
        raise RuntimeError(
            f"slicecap.mitsuba_bsdf.register: Mitsuba variant {variant} is not an RGB variant; "
            "the slicecap BSDF holds an RGB table (use e.g. scalar_rgb or llvm_ad_rgb)"
        )
    if variant in _registered_variants:
        return
    base = _make_base_class()
    table_class, analytic_class = _make_class(base), _make_analytic_class(base)
    mi.register_bsdf(PLUGIN_NAME, lambda props: table_class(props))
    mi.register_bsdf(ANALYTIC_PLUGIN_NAME, lambda props: analytic_class(props))
    _registered_variants.add(variant)
