"""Prototype measurement (not the product's fit): how much a second, isotropic GGX lobe would lower
`slicecap fit`'s dE on measured tables (issue 30), before anyone builds it in C++.

For each table it starts from the one-lobe fit's JSON (`slicecap fit`, docs/material-fit.md),
adds a second isotropic GGX lobe with its own Schlick Fresnel (RGB f0, grey f90) and alpha, and
refits every parameter in the C++ fit's own domain (lib/fit/src/material_cost.cpp, fit_data.cpp):
residual 255 (g(f cos_i / M) - g(t cos_i / M)) per light/view pair and channel, f the model, t
the table, M the table's largest cos-weighted value, g the sRGB curve continued past 1; all
81 x 81 pairs with equal weight. The solver is a small bounded Levenberg-Marquardt with a
forward-difference Jacobian (scipy is not in the project's venv), the same bounds as the C++ fit
plus [0, 1] for the second lobe's f0 and f90 and [0.002, 2] for its alpha, run from several
starts of the second lobe's alpha. The second lobe's f0 = f90 = 0 is the one-lobe model, so the
two-lobe family contains the one-lobe fit.

Before fitting, the script checks its numpy model against the C++ one: `slicecap generate
FIT.json -o T.f32` tabulates the one-lobe fit, and the numpy tabulation (second lobe at zero)
must agree to --model-tolerance relative. The dE reported is `slicecap compare TABLE
TWO_LOBE.f32 --json`'s, never a formula of this script's.

Usage: second_lobe_headroom.py --cli build/app/slicecap --tables DIR --fits DIR --out DIR
       [--min-delta-e 1] [--coat] [TABLE_NAME ...]
--coat restricts the second lobe to a clear coat: one grey f0, f90 fixed at 1.
TABLE_NAME defaults to every row of FITS/summary.tsv with delta_e above --min-delta-e.

A fit whose model has a clear coat ("ggx+coat", "ggx+sheen+coat") is refused, exit 1 naming it:
its coat already is a second lobe, layered (the base dimmed by the coat's Fresnel) where this
prototype's lobe is added, so neither its numpy model nor its headroom would mean what they say.
"""

import argparse
import json
import math
import pathlib
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from slicecap.fitted_material import (
    charlie_visibility,
    has_coat,
    has_sheen,
    read_fitted_material,
    sheen_albedo,
)
from slicecap.grid import DIRECTION_COUNT, GRID_DIRECTIONS_DEG, to_unit_vectors

ALPHA_BOUNDS = (0.002, 2.0)  # the C++ fit's (start_solver.cpp)
SHEEN_ROUGHNESS_BOUNDS = (0.05, 1.0)
SECOND_ALPHA_STARTS = (0.02, 0.08, 0.3)
# The second lobe starts dim and grey: bright enough that its alpha has a gradient, small beside
# any table's highlight.
SECOND_F0_START = 0.02


@dataclass
class Geometry:
    """Per light/view pair (light-major, as the table) what does not depend on the parameters."""

    light: np.ndarray
    view: np.ndarray
    half: np.ndarray
    fresnel_weight: np.ndarray
    sheen_visibility: np.ndarray
    log_sin2_half: np.ndarray


def grid_geometry() -> Geometry:
    vectors = to_unit_vectors(GRID_DIRECTIONS_DEG)
    light = np.repeat(vectors, DIRECTION_COUNT, axis=0)
    view = np.tile(vectors, (DIRECTION_COUNT, 1))
    half = light + view
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    cos_lh = np.clip(np.sum(light * half, axis=-1), 0.0, 1.0)
    return Geometry(
        light=light,
        view=view,
        half=half,
        fresnel_weight=(1.0 - cos_lh) ** 5,
        sheen_visibility=1.0 / (4.0 * (light[:, 2] + view[:, 2] - light[:, 2] * view[:, 2])),
        # As lobe_terms.hpp: the floor keeps 0^(1/r) finite in the logarithm at h = n.
        log_sin2_half=np.log(np.maximum(1.0 - half[:, 2] ** 2, 1e-12)),
    )


def ggx_specular(g: Geometry, alpha_t: float, alpha_b: float, tangent_rad: float) -> np.ndarray:
    """D G2 / (4 cos_i cos_v) of anisotropic GGX with height-correlated Smith (lobe_terms.hpp)."""
    c, s = math.cos(tangent_rad), math.sin(tangent_rad)

    def local(w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return w[:, 0] * c + w[:, 1] * s, -w[:, 0] * s + w[:, 1] * c

    at2, ab2 = alpha_t * alpha_t, alpha_b * alpha_b
    hx, hy = local(g.half)
    q = hx * hx / at2 + hy * hy / ab2 + g.half[:, 2] ** 2
    distribution = 1.0 / (math.pi * alpha_t * alpha_b * q * q)

    def smith_lambda(w: np.ndarray) -> np.ndarray:
        wx, wy = local(w)
        return (np.sqrt(1.0 + (at2 * wx * wx + ab2 * wy * wy) / (w[:, 2] ** 2)) - 1.0) / 2.0

    return distribution / (
        (1.0 + smith_lambda(g.light) + smith_lambda(g.view)) * (4.0 * g.light[:, 2] * g.view[:, 2])
    )


def sheen_lobe(g: Geometry, roughness: float) -> np.ndarray:
    inverse = 1.0 / roughness
    return (
        (2.0 + inverse)
        * np.exp(g.log_sin2_half * (0.5 * inverse))
        / (2.0 * math.pi)
        * g.sheen_visibility
    )


# Parameter vector: 0-2 diffuse albedo, 3-5 f0, 6 f90, 7 alpha_t, 8 alpha_b, 9 tangent (rad),
# 10-12 second lobe f0, 13 its f90, 14 its alpha, then (with sheen) 15-17 sheen colour, 18 sheen
# roughness. Alphas and the sheen roughness are fitted as logarithms (as the C++ fit does).
LOG_PARAMETERS = (7, 8, 14, 18)


def brdf(g: Geometry, p: np.ndarray, with_sheen: bool | str, coat: bool = False) -> np.ndarray:
    """(6561, 3) BRDF values (1/sr) of the two-lobe model for the parameter vector p. With `coat`
    the second lobe is a clear coat: grey f0 = p[10], f90 = 1 (p[11:14] unused). `with_sheen`:
    False, True or "additive" (the sheen added on top), or "khr_materials_sheen" (a format-2 fit's
    KHR_materials_sheen layering: Charlie visibility, both lobes and the diffuse scaled by
    1 - max(sheen) E, as slicecap.fitted_material)."""
    w = g.fresnel_weight[:, None]
    f0_second = np.full(3, p[10]) if coat else p[10:13]
    f90_second = 1.0 if coat else p[13]
    first = ggx_specular(g, p[7], p[8], p[9])[:, None]
    second = ggx_specular(g, p[14], p[14], 0.0)[:, None]
    value = (
        p[0:3] / math.pi
        + (p[3:6] + (p[6] - p[3:6]) * w) * first
        + (f0_second + (f90_second - f0_second) * w) * second
    )
    if with_sheen:
        lobe = sheen_lobe(g, p[18])
        if with_sheen == "khr_materials_sheen":
            cos_l, cos_v = g.light[:, 2], g.view[:, 2]
            lobe = lobe / g.sheen_visibility * charlie_visibility(cos_l, cos_v, p[18])
            albedo = np.maximum(sheen_albedo(cos_l, p[18]), sheen_albedo(cos_v, p[18]))
            value = value * (1.0 - np.max(p[15:18]) * albedo)[:, None]
        value = value + p[15:18] * lobe[:, None]
    return value


def srgb_curve(x: np.ndarray) -> np.ndarray:
    """The sRGB curve, continued past 1 by its power law (fit_data.hpp)."""
    return np.where(
        x <= 0.0031308, 12.92 * x, 1.055 * np.cbrt(np.maximum(x, 0.0031308)) ** 1.25 - 0.055
    )


def cos_weighted_scale(table: np.ndarray) -> np.ndarray:
    """cos(theta_i) / M per pair (eval::cosWeightedMaximum): M over the table's largest channel."""
    cos_i = to_unit_vectors(GRID_DIRECTIONS_DEG)[:, 2]
    maximum = float(np.max(table.max(axis=2) * cos_i[:, None]))
    return np.repeat(cos_i, DIRECTION_COUNT) / maximum


class CoatedFitError(ValueError):
    """A fit with a clear coat given where this prototype needs a one-lobe fit."""


def parameters_from_fit(fit_json: pathlib.Path) -> tuple[np.ndarray, bool | str]:
    """The one-lobe fit as a two-lobe vector whose second lobe is absent (f0 = f90 = 0).
    CoatedFitError for a fit with a clear coat (the module's docstring says why)."""
    m = read_fitted_material(fit_json)
    if has_coat(m.model):
        raise CoatedFitError(
            f"{fit_json}: model {m.model} has a clear coat, a second lobe already; this prototype "
            "measures a second lobe over a fit without one (ggx or ggx+sheen)")
    # The sheen's form ("khr_materials_sheen" or "additive") when there is one: brdf's with_sheen.
    with_sheen: bool | str = m.sheen_form if has_sheen(m.model) else False
    p = np.zeros(19 if with_sheen else 15)
    p[0:3] = m.diffuse_albedo
    p[3:6] = m.specular_f0
    p[6] = m.specular_f90
    p[7], p[8], p[9] = m.alpha_tangent, m.alpha_bitangent, math.radians(m.tangent_deg)
    p[14] = 0.1
    if with_sheen:
        p[15:18] = m.sheen_colour
        p[18] = m.sheen_roughness
    return p, with_sheen


def bounds(size: int) -> tuple[np.ndarray, np.ndarray]:
    lower = np.zeros(size)
    upper = np.full(size, np.inf)
    upper[3:7] = 1.0
    upper[10:14] = 1.0
    lower[9], upper[9] = -np.inf, np.inf
    for i in (7, 8, 14):
        lower[i], upper[i] = ALPHA_BOUNDS
    if size > 15:
        lower[18], upper[18] = SHEEN_ROUGHNESS_BOUNDS
    return lower, upper


def _map_log_parameters(values: np.ndarray, function: Callable[[float], float]) -> np.ndarray:
    """A copy of `values` with `function` (math.log or math.exp) applied to the alphas and the
    sheen roughness that the solver moves in logs (LOG_PARAMETERS present in this size)."""
    mapped = values.copy()
    for i in LOG_PARAMETERS:
        if i < mapped.size:
            mapped[i] = function(mapped[i])
    return mapped


def to_internal(p: np.ndarray) -> np.ndarray:
    return _map_log_parameters(p, math.log)


def to_external(x: np.ndarray) -> np.ndarray:
    return _map_log_parameters(x, math.exp)


def internal_bounds(size: int) -> tuple[np.ndarray, np.ndarray]:
    lower, upper = bounds(size)
    return _map_log_parameters(lower, math.log), _map_log_parameters(upper, math.log)


def residuals(g: Geometry, x: np.ndarray, with_sheen: bool | str, scale: np.ndarray,
              target: np.ndarray, coat: bool = False) -> np.ndarray:
    value = brdf(g, to_external(x), with_sheen, coat)
    return (255.0 * srgb_curve(value * scale[:, None]) - target).ravel()


def levenberg_marquardt(g: Geometry, x0: np.ndarray, with_sheen: bool | str, scale: np.ndarray,
                        target: np.ndarray, max_iterations: int,
                        coat: bool = False) -> tuple[np.ndarray, float, int]:
    """Bounded LM: a parameter on a bound whose gradient pushes it out is held for that step,
    a step is projected onto the box. Returns (x, cost = sum r^2 / 2, iterations)."""
    lower, upper = internal_bounds(x0.size)
    x = np.clip(x0, lower, upper)
    r = residuals(g, x, with_sheen, scale, target, coat)
    cost = 0.5 * float(r @ r)
    damping = 1e-3
    iterations = 0
    for _ in range(max_iterations):
        iterations += 1
        jacobian = np.empty((r.size, x.size))
        for k in range(x.size):
            step = 1e-7 * max(1.0, abs(x[k]))
            # Step inward from an upper bound, so the model is evaluated inside the box.
            if x[k] + step > upper[k]:
                step = -step
            shifted = x.copy()
            shifted[k] += step
            jacobian[:, k] = (residuals(g, shifted, with_sheen, scale, target, coat) - r) / step
        gradient = jacobian.T @ r
        held = ((x <= lower) & (gradient > 0)) | ((x >= upper) & (gradient < 0))
        free = ~held
        if coat:
            free[11:14] = False  # the coat's f0 is p[10] alone and its f90 is 1
        normal = jacobian[:, free].T @ jacobian[:, free]
        improved = False
        while damping < 1e12:
            a = normal + damping * np.diag(np.maximum(np.diag(normal), 1e-12))
            try:
                delta = np.linalg.solve(a, -gradient[free])
            except np.linalg.LinAlgError:
                damping *= 10.0
                continue
            candidate = x.copy()
            candidate[free] += delta
            candidate = np.clip(candidate, lower, upper)
            r_new = residuals(g, candidate, with_sheen, scale, target, coat)
            cost_new = 0.5 * float(r_new @ r_new)
            if np.isfinite(cost_new) and cost_new < cost:
                relative = (cost - cost_new) / cost
                x, r, cost = candidate, r_new, cost_new
                damping = max(damping / 3.0, 1e-9)
                improved = True
                break
            damping *= 10.0
        if not improved or relative < 1e-9:
            break
    return x, cost, iterations


def tabulate(g: Geometry, p: np.ndarray, with_sheen: bool | str, coat: bool = False) -> np.ndarray:
    return brdf(g, p, with_sheen, coat).reshape(DIRECTION_COUNT, DIRECTION_COUNT, 3)


def read_f32(path: pathlib.Path) -> np.ndarray:
    values = np.fromfile(path, dtype="<f4")
    return values.reshape(DIRECTION_COUNT, DIRECTION_COUNT, 3).astype(np.float64)


def write_f32(path: pathlib.Path, table: np.ndarray) -> None:
    np.asarray(table, dtype="<f4").tofile(path)


def model_mismatch(cli: pathlib.Path, fit_json: pathlib.Path, g: Geometry) -> float:
    """Largest |numpy - C++| / |C++| over the fit's table, C++ values below 1e-6 of the table's
    largest floored there (a relative error of a value near zero says nothing)."""
    p, with_sheen = parameters_from_fit(fit_json)
    with tempfile.TemporaryDirectory() as directory:
        out = pathlib.Path(directory) / "fit.f32"
        subprocess.run([str(cli), "generate", str(fit_json), "-o", str(out)], check=True,
                       capture_output=True)
        reference = read_f32(out)
    ours = tabulate(g, p, with_sheen)
    floor = 1e-6 * float(np.max(np.abs(reference)))
    return float(np.max(np.abs(ours - reference) / np.maximum(np.abs(reference), floor)))


def compare_delta_e(cli: pathlib.Path, reference: pathlib.Path, test: pathlib.Path) -> float:
    out = subprocess.run([str(cli), "compare", str(reference), str(test), "--json"], check=True,
                         capture_output=True, text=True)
    return float(json.loads(out.stdout)["delta_e"])


def fit_two_lobes(g: Geometry, table: np.ndarray, fit_json: pathlib.Path,
                  max_iterations: int, coat: bool = False) -> dict:
    p_one, with_sheen = parameters_from_fit(fit_json)
    scale = cos_weighted_scale(table)
    target = 255.0 * srgb_curve(table.reshape(-1, 3) * scale[:, None])
    r_one = residuals(g, to_internal(p_one), with_sheen, scale, target)
    best = None
    for alpha in SECOND_ALPHA_STARTS:
        start = p_one.copy()
        start[10:14] = SECOND_F0_START
        start[14] = alpha
        x, cost, iterations = levenberg_marquardt(g, to_internal(start), with_sheen, scale,
                                                  target, max_iterations, coat)
        if best is None or cost < best["cost"]:
            best = {"cost": cost, "x": x, "start_alpha": alpha, "iterations": iterations}
    assert best is not None
    best["p"] = to_external(best["x"])
    if coat:  # report the coat as the general lobe it is: grey f0, f90 = 1
        best["p"][11:13] = best["p"][10]
        best["p"][13] = 1.0
    best["with_sheen"] = with_sheen
    best["one_lobe_cost"] = 0.5 * float(r_one @ r_one)
    return best


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", type=pathlib.Path, required=True)
    parser.add_argument("--tables", type=pathlib.Path, required=True,
                        help="directory of NAME.f32 tables")
    parser.add_argument("--fits", type=pathlib.Path, required=True,
                        help="directory of NAME.json one-lobe fits and summary.tsv")
    parser.add_argument("--out", type=pathlib.Path, required=True)
    parser.add_argument("--min-delta-e", type=float, default=1.0)
    parser.add_argument("--max-iterations", type=int, default=60)
    parser.add_argument("--model-tolerance", type=float, default=1e-5)
    parser.add_argument("--coat", action="store_true",
                        help="second lobe as a clear coat: grey f0, f90 = 1 (two parameters)")
    parser.add_argument("names", nargs="*")
    args = parser.parse_args(argv)

    one_lobe_delta_e = {}
    for line in (args.fits / "summary.tsv").read_text().splitlines()[1:]:
        fields = line.split("\t")
        one_lobe_delta_e[fields[0]] = float(fields[3])
    names = args.names or [n for n, de in one_lobe_delta_e.items() if de > args.min_delta_e]
    args.out.mkdir(parents=True, exist_ok=True)
    g = grid_geometry()
    header = ("table\tmodel\tone_lobe_delta_e\ttwo_lobe_delta_e\tdrop\tearns\tsecond_f0_r\t"
              "second_f0_g\tsecond_f0_b\tsecond_f90\tsecond_alpha\tstart_alpha\tfirst_alpha_t\t"
              "first_alpha_b\tcost_ratio\tmodel_mismatch\tcpu_s")
    rows = [header]
    print(header, flush=True)
    earning = 0
    for name in names:
        fit_json = args.fits / f"{name}.json"
        table_path = args.tables / f"{name}.f32"
        try:
            mismatch = model_mismatch(args.cli, fit_json, g)
        except CoatedFitError as e:
            print(e, file=sys.stderr)
            return 1
        if not mismatch <= args.model_tolerance:
            print(f"{name}: numpy model differs from `slicecap generate` by {mismatch:.3g} "
                  f"(relative), above {args.model_tolerance}", file=sys.stderr)
            return 1
        cpu_start = time.process_time()
        best = fit_two_lobes(g, read_f32(table_path), fit_json, args.max_iterations,
                             args.coat)
        cpu_s = time.process_time() - cpu_start
        p = best["p"]
        out_table = args.out / f"{name}.two-lobe.f32"
        write_f32(out_table, tabulate(g, p, best["with_sheen"]))
        two = compare_delta_e(args.cli, table_path, out_table)
        one = one_lobe_delta_e[name]
        drop = one - two
        earns = drop >= 0.1 and two <= 0.9 * one  # the rule that admits the sheen
        earning += earns
        (args.out / f"{name}.two-lobe.json").write_text(json.dumps({
            "prototype": "second_lobe_headroom.py, not the product's fit",
            "table": str(table_path), "one_lobe_fit": str(fit_json),
            "parameters": p.tolist(), "with_sheen": best["with_sheen"], "coat": args.coat,
            "delta_e": two, "one_lobe_delta_e": one, "start_alpha": best["start_alpha"],
            "iterations": best["iterations"], "cost": best["cost"],
            "one_lobe_cost": best["one_lobe_cost"]}, indent=1))
        row = (f"{name}\t{'ggx+sheen' if best['with_sheen'] else 'ggx'}\t{one:.3f}\t{two:.3f}\t"
               f"{drop:.3f}\t{'yes' if earns else 'no'}\t{p[10]:.4f}\t{p[11]:.4f}\t{p[12]:.4f}\t"
               f"{p[13]:.4f}\t{p[14]:.4f}\t{best['start_alpha']}\t{p[7]:.4f}\t{p[8]:.4f}\t"
               f"{best['cost'] / best['one_lobe_cost']:.3f}\t{mismatch:.2g}\t{cpu_s:.1f}")
        rows.append(row)
        print(row, flush=True)
    (args.out / "summary.tsv").write_text("\n".join(rows) + "\n")
    print(f"{earning} of {len(names)} tables: dE drops by >= 10 % and >= 0.1", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
