"""slicecap.analytic_models reproduces the C++ built-in materials: at the 81 x 81 grid directions
it gives `slicecap generate NAME`'s table for every built-in material (parameters read from the
CLI's own descriptions), and a tangent turned the other way is far outside that tolerance. The
Mitsuba BSDF `slicecap_analytic` evaluates the same formulas in Dr.Jit and, at the grid's nodes,
what the table plugin `slicecap` reads from the table."""

import subprocess

import numpy as np
import pytest

from slicecap import read_abrdf_exr, tabulate, write_abrdf_exr
from slicecap.abrdf_exr import SlicecapFileError
from slicecap.analytic_models import (
    AnalyticModel,
    Term,
    built_in_models,
    model_of_table,
    parse_model,
)
from slicecap.grid import GRID_DIRECTIONS_DEG, to_unit_vectors

# The C++ tabulates in double and stores float32; this evaluates in double and rounds the same
# way. Seen: every entry of every built-in table bit-identical (relative difference 0); 1e-6 is
# ~16 float32 steps, room for another libm's exp/pow/sqrt, far below what a wrong term changes.
RTOL = 1e-6


@pytest.fixture(scope="module")
def generated(slicecap_cli_for_module, tmp_path_factory):
    """name -> (model parsed from `generate --list`, the table `generate NAME` wrote, its path)."""
    folder = tmp_path_factory.mktemp("generated")
    tables = {}
    for name, model in built_in_models(slicecap_cli_for_module).items():
        path = folder / f"{name}.exr"
        subprocess.run([slicecap_cli_for_module, "generate", name, "-o", path], check=True,
                       capture_output=True)
        tables[name] = (model, read_abrdf_exr(path).values.astype(np.float64), path)
    return tables


def relative_difference(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b) / np.abs(b)))


def with_tangent(model: AnalyticModel, turn) -> AnalyticModel:
    terms = tuple(
        Term(t.kind, {**t.parameters, "tangent_deg": turn(t.parameters["tangent_deg"])})
        if "tangent_deg" in t.parameters else t
        for t in model.terms
    )
    return AnalyticModel(model.description, terms)


def test_the_cli_lists_the_eight_anisotropic_materials_and_every_term_kind(generated):
    anisotropic = [n for n, (m, _, _) in generated.items() if m.tangent_deg is not None]
    assert len(anisotropic) == 8, anisotropic
    kinds = {t.kind for m, _, _ in generated.values() for t in m.terms}
    assert {"ggx", "ward", "sheen", "lambert", "blinn-phong"} <= kinds


def test_reproduces_every_built_in_table_of_generate(generated):
    worst = {}
    for name, (model, table, path) in generated.items():
        assert np.all(table > 0.0), name  # the relative difference below is defined
        assert model_of_table(path) == model  # the EXR's slicecap:model is the same description
        worst[name] = relative_difference(tabulate(model.evaluate).astype(np.float64), table)
    assert max(worst.values()) <= RTOL, worst


def test_a_tangent_turned_the_other_way_is_far_outside_the_tolerance(generated):
    # A sign error in the frame (tangent at -t instead of +t) changes nothing for tangents at 0
    # and 90 deg (those lobes are mirror-symmetric), so the materials tangent elsewhere show it.
    turned = 0
    for name, (model, table, _) in generated.items():
        tangent = model.tangent_deg
        if tangent is None or tangent % 90.0 == 0.0:
            continue
        flipped = with_tangent(model, lambda t: -t)
        assert relative_difference(tabulate(flipped.evaluate).astype(np.float64), table) > 0.1, name
        turned += 1
    assert turned >= 5


def test_refuses_what_is_not_an_analytic_model(tmp_path):
    with pytest.raises(ValueError, match="'table' is not an analytic model"):
        parse_model("table satin.exr")
    with pytest.raises(ValueError, match="missing tangent_deg"):
        parse_model("ggx diffuse=0/0/0 f0=0.9/0.9/0.9 ax=0.1 ay=0.2")
    with pytest.raises(ValueError, match="f0 takes 3"):
        parse_model("ggx diffuse=0/0/0 f0=0.9 ax=0.1 ay=0.2 tangent_deg=0")
    write_abrdf_exr(tmp_path / "captured.exr", np.full((81, 81, 3), 0.1, dtype=np.float32))
    with pytest.raises(SlicecapFileError, match="captured.exr: not an analytic table"):
        model_of_table(tmp_path / "captured.exr")


def test_below_the_surface_is_zero():
    model = parse_model("lambert albedo=0.5/0.5/0.5")
    light = np.array([[0.0, 0.6, -0.8], [0.0, 0.0, 1.0]])
    value = model.evaluate(light, np.array([[0.0, 0.0, 1.0]] * 2))
    np.testing.assert_allclose(value, [[0.0] * 3, [0.5 / np.pi] * 3])


# The Mitsuba BSDF (llvm variant; skipped without Mitsuba or a usable libLLVM).


def eval_bsdf(mi, bsdf, view: np.ndarray, light: np.ndarray, mode) -> np.ndarray:
    """A BSDF's BRDF (eval / cos theta of wo) for camera-side `view` and `light` unit vectors."""
    import drjit as dr

    si = dr.zeros(mi.SurfaceInteraction3f, len(view))
    wi, wo = (view, light) if mode == mi.TransportMode.Radiance else (light, view)
    si.wi = mi.Vector3f(*(wi[:, i] for i in range(3)))
    value = bsdf.eval(mi.BSDFContext(mode), si, mi.Vector3f(*(wo[:, i] for i in range(3))))
    return np.array(value).reshape(3, -1).T / wo[:, 2:3]


@pytest.fixture
def llvm():
    from mitsuba_support import use_variant

    return use_variant("llvm_ad_rgb")


def test_mitsuba_bsdf_evaluates_the_model_and_the_tables_nodes(llvm, generated):
    mi = llvm
    rng = np.random.default_rng(7)
    n = 3000
    light = to_unit_vectors(np.stack([rng.uniform(0.5, 89, n), rng.uniform(0, 360, n)], -1))
    view = to_unit_vectors(np.stack([rng.uniform(0.5, 89, n), rng.uniform(0, 360, n)], -1))
    nodes = to_unit_vectors(GRID_DIRECTIONS_DEG)
    node_light, node_view = np.repeat(nodes, 81, axis=0), np.tile(nodes, (81, 1))
    for name, (model, _, path) in generated.items():
        if model.tangent_deg is None:
            continue
        by_file = mi.load_dict({"type": "slicecap_analytic", "filename": str(path)})
        by_text = mi.load_dict({"type": "slicecap_analytic", "model": model.description})
        expected = model.evaluate(light, view)
        for bsdf in (by_file, by_text):
            for mode in (mi.TransportMode.Radiance, mi.TransportMode.Importance):
                # float32 against float64: seen <= 1e-5 relative.
                np.testing.assert_allclose(eval_bsdf(mi, bsdf, view, light, mode), expected,
                                           rtol=1e-4, err_msg=name)
        # At the grid's nodes the table plugin reads the table's entries: the same frame (x on
        # dp/du, azimuth counter-clockwise). float32 angles land a hair off a node and pull in a
        # neighbour's entry (seen <= 0.4 % of the entry, 1e-3 of the largest as a floor).
        truth = eval_bsdf(mi, by_file, node_view, node_light, mi.TransportMode.Radiance)
        table = mi.load_dict({"type": "slicecap", "filename": str(path)})
        read = eval_bsdf(mi, table, node_view, node_light, mi.TransportMode.Radiance)
        floor = 1e-3 * read.max()
        assert np.max(np.abs(truth - read) / np.maximum(read, floor)) < 1e-2, name


def test_mitsuba_bsdf_needs_one_source(llvm):
    with pytest.raises(RuntimeError, match="give one of the properties 'model'"):
        llvm.load_dict({"type": "slicecap_analytic"})


@pytest.mark.parametrize(
    ("description", "flipped", "largest"),
    [
        ("lambert albedo=0.6/0.55/0.5", None, 1e-5),
        ("ward diffuse=0.2/0.2/0.2 specular=0.3/0.3/0.3 ax=0.4 ay=0.8 tangent_deg=60",
         "tangent_deg=-60", 0.05),
        ("ggx diffuse=0.05/0.05/0.05 f0=0.9/0.9/0.9 ax=0.5 ay=1 tangent_deg=30",
         "tangent_deg=-30", 0.05),
    ],
)
def test_a_broad_lobe_renders_like_its_table(llvm, tmp_path, description, flipped, largest):
    """Rendered on a sphere under point lights, the truth and its table through the table plugin
    agree where the grid resolves the lobe (a constant: to float precision; seen 1.5 % and 2.8 %
    relative L1 for these lobes), and a tangent turned the other way is far from both (seen 15 %
    and 55 %): the two BSDFs shade in the same frame."""
    from mitsuba_support import render, sphere_scene

    mi = llvm
    model = parse_model(description)
    write_abrdf_exr(tmp_path / "table.exr", tabulate(model.evaluate))
    truth = render(mi, sphere_scene(mi, {"type": "slicecap_analytic", "model": description},
                                    lights="points"))
    table_bsdf = {"type": "slicecap", "filename": str(tmp_path / "table.exr")}
    table = render(mi, sphere_scene(mi, table_bsdf, lights="points"))

    def relative_l1(image, reference):
        return float(np.abs(image - reference).sum() / reference.sum())

    assert truth.sum() > 0.0
    assert relative_l1(table, truth) < largest
    if flipped:
        turned = description.replace(flipped.replace("-", ""), flipped)
        assert turned != description
        wrong = render(mi, sphere_scene(mi, {"type": "slicecap_analytic", "model": turned},
                                        lights="points"))
        assert relative_l1(wrong, table) > 3.0 * largest


def test_mitsuba_bsdf_in_the_scalar_variant():
    from mitsuba_support import use_variant

    mi = use_variant("scalar_rgb")
    import drjit as dr

    description = ("sheen diffuse=0.02/0.12/0.04 sheen=0.3/0.6/0.35 roughness=0.35 + ward "
                   "diffuse=0/0/0 specular=0.05/0.1/0.06 ax=0.3 ay=0.6 tangent_deg=20")
    bsdf = mi.load_dict({"type": "slicecap_analytic", "model": description})
    view = np.array([0.3, 0.1, np.sqrt(0.9)])
    light = np.array([-0.5, 0.2, np.sqrt(0.71)])
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(*(float(x) for x in view))
    wo = mi.Vector3f(*(float(x) for x in light))
    value = np.array(bsdf.eval(mi.BSDFContext(), si, wo)) / light[2]
    np.testing.assert_allclose(value, parse_model(description).evaluate(light, view), rtol=1e-5)
    bs, weight = bsdf.sample(mi.BSDFContext(), si, 0.3, mi.Point2f(0.2, 0.7))
    assert bs.wo.z > 0 and bs.pdf > 0 and np.all(np.array(weight) > 0)
