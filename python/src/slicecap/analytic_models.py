"""slicecap's built-in analytic reflectance models (lib/models, reflectance_models.cpp),
evaluated in Python term for term: Lambert, anisotropic Ward, anisotropic GGX, Blinn-Phong, the
elevation lobe and the Charlie sheen, and sums of them.

A model is read from the one-line description the C++ side prints for it (`ReflectanceModel::
describe`): the lines of `slicecap generate --list`, and the `slicecap:model` attribute of every
table `slicecap generate` writes, e.g.

    ggx diffuse=0.03/0.03/0.03 f0=0.56/0.57/0.58 ax=0.1 ay=0.4 tangent_deg=30
    sheen diffuse=0.02/0.12/0.04 sheen=0.3/0.6/0.35 roughness=0.35 + ward diffuse=0/0/0 ...

so the parameters come from the code that defines the materials, not from a copy of them. The
description prints six significant digits, enough for the built-in materials (their tables are
reproduced to float precision, python/tests/test_analytic_models.py); a model specification with
more digits is evaluated with the rounded ones.

The frame is the table's (docs/method.md §1.2): z = the normal, x = the Bonn grid's azimuth 0,
azimuths counter-clockwise; an anisotropic term's tangent lies at `tangent_deg` from x. Values are
BRDFs in 1/sr without the cos(theta) factor, as the tables store them.

The formulas are written once over a numeric namespace (numpy, or drjit for the Mitsuba BSDF
`slicecap_analytic` in slicecap.mitsuba_bsdf), so the BSDF renders what this module is tested for.
Use: the exact truth behind a table of the virtual rig, `slicecap generate` or `slicecap simulate`,
e.g. rendered beside the table to see what the 81-direction grid's interpolation costs.
"""

import math
import os
import re
import subprocess
from dataclasses import dataclass
from typing import Any

import numpy as np

from slicecap.abrdf_exr import SlicecapFileError, read_abrdf_exr
from slicecap.paths import StrPath

# Parameter names of each kind of term and how many numbers each takes (3: an RGB "r/g/b").
TERM_PARAMETERS: dict[str, dict[str, int]] = {
    "lambert": {"albedo": 3},
    "ward": {"diffuse": 3, "specular": 3, "ax": 1, "ay": 1, "tangent_deg": 1},
    "ggx": {"diffuse": 3, "f0": 3, "ax": 1, "ay": 1, "tangent_deg": 1},
    "blinn-phong": {"diffuse": 3, "specular": 3, "n": 1},
    "elevation-lobe": {"k": 3, "n": 1},
    "sheen": {"diffuse": 3, "sheen": 3, "roughness": 1},
}
# Numbers per lane: numpy arrays (or floats), or Dr.Jit arrays in the Mitsuba BSDF. The module of
# the math functions (sqrt, exp, power, maximum, clip) is passed along: numpy or drjit.
Value = Any
Namespace = Any
Channels = tuple[Value, Value, Value]


@dataclass(frozen=True)
class Term:
    """One term of a model: its kind (a key of TERM_PARAMETERS) and its parameters (a float, or
    an (r, g, b) tuple)."""

    kind: str
    parameters: dict[str, Any]

    def channels(
        self, light: tuple[Value, Value, Value], view: tuple[Value, Value, Value], xp: Namespace
    ) -> Channels:
        """(r, g, b) of this term for unit vectors toward the light and the viewer, given as
        (x, y, z) component arrays in the table's frame (both z > 0)."""
        p = self.parameters
        if self.kind == "lambert":
            return _scaled(p["albedo"], 1.0 / math.pi, light[2])
        if self.kind == "ward":
            return _ward(p, light, view, xp)
        if self.kind == "ggx":
            return _ggx(p, light, view, xp)
        if self.kind == "blinn-phong":
            _, _, hz = _half(light, view, xp)
            lobe = (p["n"] + 2.0) / (8.0 * math.pi) * xp.power(hz, p["n"])
            return _plus(_scaled(p["diffuse"], 1.0 / math.pi, hz), _scaled(p["specular"], lobe, hz))
        if self.kind == "elevation-lobe":
            return _scaled(p["k"], xp.power(light[2] * view[2], p["n"]), light[2])
        if self.kind == "sheen":
            return _sheen(p, light, view, xp)
        raise ValueError(f"unknown term kind {self.kind!r}")


@dataclass(frozen=True)
class AnalyticModel:
    """A built-in analytic material: the sum of its terms, as lib/models' SumModel."""

    description: str
    terms: tuple[Term, ...]

    def channels(
        self, light: tuple[Value, Value, Value], view: tuple[Value, Value, Value], xp: Namespace
    ) -> Channels:
        """(r, g, b) for component arrays of unit vectors toward the light and the viewer, both
        above the surface; xp is numpy or drjit."""
        total = self.terms[0].channels(light, view, xp)
        for term in self.terms[1:]:
            total = _plus(total, term.channels(light, view, xp))
        return total

    def evaluate(self, to_light: np.ndarray, to_view: np.ndarray) -> np.ndarray:
        """(..., 3) RGB BRDF in 1/sr for (..., 3) unit vectors toward the light and the viewer in
        the table's frame (a slicecap.grid.Brdf); 0 where either is at or below the surface, where
        the tables hold nothing."""
        light = np.asarray(to_light, dtype=np.float64)
        view = np.asarray(to_view, dtype=np.float64)
        above = (light[..., 2] > 0.0) & (view[..., 2] > 0.0)
        # Below-horizon pairs get a harmless stand-in so that no division warns; they are zeroed.
        light = np.where(above[..., None], light, [0.0, 0.0, 1.0])
        view = np.where(above[..., None], view, [0.0, 0.0, 1.0])
        with np.errstate(under="ignore"):
            rgb = self.channels(
                (light[..., 0], light[..., 1], light[..., 2]),
                (view[..., 0], view[..., 1], view[..., 2]),
                np,
            )
        value = np.stack(np.broadcast_arrays(*rgb), axis=-1)
        return np.where(above[..., None], value, 0.0)

    @property
    def tangent_deg(self) -> float | None:
        """The tangent azimuth of the first anisotropic term (ax != ay), or None."""
        for term in self.terms:
            if term.kind in ("ward", "ggx") and term.parameters["ax"] != term.parameters["ay"]:
                return float(term.parameters["tangent_deg"])
        return None


def _plus(a: Channels, b: Channels) -> Channels:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def _scaled(rgb: tuple[float, float, float], factor: Value, like: Value) -> Channels:
    """rgb * factor per channel, as arrays shaped like `like` even when factor is a constant."""
    zero = 0.0 * like
    return (zero + rgb[0] * factor, zero + rgb[1] * factor, zero + rgb[2] * factor)


def _half(light: tuple, view: tuple, xp: Namespace) -> tuple[Value, Value, Value]:
    hx, hy, hz = light[0] + view[0], light[1] + view[1], light[2] + view[2]
    length = xp.sqrt(hx * hx + hy * hy + hz * hz)
    return hx / length, hy / length, hz / length


def _to_tangent_frame(w: tuple, tangent_deg: float) -> tuple[Value, Value, Value]:
    """w in the frame whose x axis lies at azimuth tangent_deg (the C++ TangentFrame::toLocal)."""
    c, s = math.cos(math.radians(tangent_deg)), math.sin(math.radians(tangent_deg))
    return w[0] * c + w[1] * s, -w[0] * s + w[1] * c, w[2]


def _ward(p: dict, light: tuple, view: tuple, xp: Namespace) -> Channels:
    hx, hy, hz = _to_tangent_frame(_half(light, view, xp), p["tangent_deg"])
    ax, ay = p["ax"], p["ay"]
    exponent = -(hx * hx / (ax * ax) + hy * hy / (ay * ay)) / (hz * hz)
    lobe = xp.exp(exponent) / (4.0 * math.pi * ax * ay * xp.sqrt(light[2] * view[2]))
    return _plus(_scaled(p["diffuse"], 1.0 / math.pi, hz), _scaled(p["specular"], lobe, hz))


def _ggx(p: dict, light: tuple, view: tuple, xp: Namespace) -> Channels:
    ax, ay = p["ax"], p["ay"]
    lx, ly, lz = _to_tangent_frame(light, p["tangent_deg"])
    vx, vy, vz = _to_tangent_frame(view, p["tangent_deg"])
    hx, hy, hz = _half((lx, ly, lz), (vx, vy, vz), xp)
    s = hx * hx / (ax * ax) + hy * hy / (ay * ay) + hz * hz
    distribution = 1.0 / (math.pi * ax * ay * s * s)

    def smith_lambda(x: Value, y: Value, z: Value) -> Value:
        return (-1.0 + xp.sqrt(1.0 + (ax * ax * x * x + ay * ay * y * y) / (z * z))) / 2.0

    masking = 1.0 / (1.0 + smith_lambda(lx, ly, lz) + smith_lambda(vx, vy, vz))
    cos_lh = xp.clip(lx * hx + ly * hy + lz * hz, 0.0, 1.0)
    one_minus = 1.0 - cos_lh
    schlick = one_minus * one_minus * one_minus * one_minus * one_minus
    common = distribution * masking / (4.0 * lz * vz)
    f0 = p["f0"]
    specular = tuple((f0[c] + (1.0 - f0[c]) * schlick) * common for c in range(3))
    return _plus(_scaled(p["diffuse"], 1.0 / math.pi, hz), specular)


def _sheen(p: dict, light: tuple, view: tuple, xp: Namespace) -> Channels:
    _, _, hz = _half(light, view, xp)
    sin_h = xp.sqrt(xp.maximum(1.0 - hz * hz, 0.0))
    inverse_r = 1.0 / p["roughness"]
    distribution = (2.0 + inverse_r) * xp.power(sin_h, inverse_r) / (2.0 * math.pi)
    visibility = 1.0 / (4.0 * (light[2] + view[2] - light[2] * view[2]))
    return _plus(
        _scaled(p["diffuse"], 1.0 / math.pi, hz), _scaled(p["sheen"], distribution * visibility, hz)
    )


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_VALUE = re.compile(rf"^{_NUMBER}(?:/{_NUMBER}/{_NUMBER})?$")


def parse_model(description: str) -> AnalyticModel:
    """The model of a C++ description (`ReflectanceModel::describe`): terms joined by " + ", each
    "KIND key=value ..." with RGB values as r/g/b. Raises ValueError naming the text for what is
    not one of the analytic kinds (e.g. "table NAME", a woven material) or lacks a parameter."""
    terms = []
    for text in description.strip().split(" + "):
        words = text.split()
        if not words or words[0] not in TERM_PARAMETERS:
            kind = words[0] if words else ""
            raise ValueError(
                f"{description!r}: {kind!r} is not an analytic model "
                f"(one of {', '.join(TERM_PARAMETERS)})"
            )
        kind, wanted = words[0], TERM_PARAMETERS[words[0]]
        parameters: dict[str, Any] = {}
        for word in words[1:]:
            key, _, raw = word.partition("=")
            if key not in wanted or key in parameters or not _VALUE.match(raw):
                raise ValueError(f"{description!r}: {kind}: unexpected parameter {word!r}")
            numbers = tuple(float(x) for x in raw.split("/"))
            if len(numbers) != wanted[key]:
                raise ValueError(f"{description!r}: {kind}: {key} takes {wanted[key]} number(s)")
            parameters[key] = numbers if wanted[key] == 3 else numbers[0]
        missing = [k for k in wanted if k not in parameters]
        if missing:
            raise ValueError(f"{description!r}: {kind}: missing {', '.join(missing)}")
        terms.append(Term(kind, parameters))
    return AnalyticModel(description.strip(), tuple(terms))


def built_in_models(cli: StrPath) -> dict[str, AnalyticModel]:
    """Every built-in material of the `slicecap` command `cli` (its `generate --list`: a name,
    two spaces, the description), by name."""
    listing = subprocess.run(
        [os.fspath(cli), "generate", "--list"], check=True, capture_output=True, text=True
    ).stdout
    models = {}
    for line in listing.splitlines():
        if line.strip():
            name, _, description = line.partition("  ")
            models[name.strip()] = parse_model(description)
    return models


def model_of_table(path: StrPath) -> AnalyticModel:
    """The analytic model behind a table `slicecap generate` wrote (its `slicecap:method` is
    "analytic", its `slicecap:model` the description). Raises SlicecapFileError naming the file
    for any other table (a capture, a fit)."""
    attributes = read_abrdf_exr(path).attributes
    if attributes.get("method") != "analytic" or "model" not in attributes:
        raise SlicecapFileError(
            f"{os.fspath(path)}: not an analytic table of `slicecap generate` (slicecap:method is "
            f"{attributes.get('method')!r}); it names no model to evaluate"
        )
    try:
        return parse_model(attributes["model"])
    except ValueError as e:
        raise SlicecapFileError(f"{os.fspath(path)}: {e}") from e
