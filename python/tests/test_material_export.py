"""The material exports of `slicecap fit --gltf/--mtlx/--mitsuba` (docs/material-export.md), read
by the real consumers: the Khronos glTF validator (npm gltf-validator, scripts/consumers-install)
finds no errors, MaterialX's own Python package validates the .mtlx and generates GLSL for both
of its materials, and Mitsuba 3 loads the snippet, evaluates a BSDF close to the fitted one and
renders.
Each skips with its reason only when that consumer is not installed."""

import json
import math
import pathlib
import platform
import shutil
import subprocess
import sys

import numpy as np
import pytest
from conftest import REPOSITORY, find_slicecap_cli
from material_export_support import (
    fitted_brdf,
    khr_sheen_rest_scaling,
    mitsuba_ratios,
    sheen_stand_in,
)
from mitsuba_support import render, sphere_scene, use_variant

sys.path.insert(0, str(REPOSITORY / "python" / "checks"))
from lacquer import LACQUER  # noqa: E402  (python/checks/lacquer.py: the coated truth)

CONSUMERS = REPOSITORY / "tools" / "consumers"
VALIDATOR = CONSUMERS / "node_modules" / "gltf-validator"

# A brushed metal the model family matches (GGX from GGX), a velvet whose fit has a sheen term and
# a lacquer whose fit has a clear coat (LACQUER, tabulated by `slicecap generate` from its JSON).
MATERIALS = ("brushed-steel-30", "velvet-red", "lacquer")


def generate(cli, name: str, table: pathlib.Path) -> None:
    if name == "lacquer":
        truth = table.with_name("lacquer-truth.json")
        truth.write_text(json.dumps(LACQUER))
        name = str(truth)
    subprocess.run([cli, "generate", name, "-o", table], check=True, capture_output=True)


@pytest.fixture(scope="module")
def exports(tmp_path_factory) -> dict:
    """Each material generated, fitted and exported once: {name: {kind: path}}."""
    cli = find_slicecap_cli()
    root = tmp_path_factory.mktemp("exports")
    out = {}
    for name in MATERIALS:
        table = root / f"{name}.exr"
        generate(cli, name, table)
        files = {
            "json": root / f"{name}.json",
            "gltf": root / f"{name}.gltf",
            "glb": root / f"{name}.glb",
            "mtlx": root / f"{name}.mtlx",
            "mitsuba": root / f"{name}.xml",
        }
        subprocess.run(
            [cli, "fit", table, "-o", files["json"], "--gltf", files["gltf"], "--mtlx",
             files["mtlx"], "--mitsuba", files["mitsuba"]],
            check=True, capture_output=True)
        # The binary container from the JSON: the export of an earlier fit.
        subprocess.run([cli, "fit", files["json"], "--gltf", files["glb"]], check=True,
                       capture_output=True)
        out[name] = files
    return out


def validate_gltf(path: pathlib.Path) -> dict:
    node = shutil.which("node")
    if node is None or not VALIDATOR.is_dir():
        pytest.skip("the glTF validator is not installed (node and scripts/consumers-install)")
    run = subprocess.run([node, CONSUMERS / "validate-gltf.mjs", path], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode in (0, 1), run.stderr
    return json.loads(run.stdout)


@pytest.mark.parametrize("name", MATERIALS)
@pytest.mark.parametrize("kind", ["gltf", "glb"])
def test_gltf_passes_the_khronos_validator(exports, name, kind):
    report = validate_gltf(exports[name][kind])
    issues = report["issues"]
    errors = [m for m in issues["messages"] if m["severity"] == 0]
    assert issues["numErrors"] == 0, errors
    # Warnings too: none today (the infos are the validator not knowing that anisotropy uses
    # TANGENT without a normal texture, and TEXCOORD_0 that no texture reads).
    assert issues["numWarnings"] == 0, issues["messages"]
    used = set(report["info"]["extensionsUsed"])
    assert {"KHR_materials_anisotropy", "KHR_materials_specular", "KHR_materials_ior"} <= used
    fitted = json.loads(exports[name]["json"].read_text())
    assert ("KHR_materials_sheen" in used) == ("sheen" in fitted["model"])
    assert ("KHR_materials_clearcoat" in used) == ("coat" in fitted["model"])


@pytest.mark.parametrize("name", MATERIALS)
def test_gltf_check_agrees_with_a_second_evaluator_of_the_specifications(exports, name, tmp_path):
    """The export's own measure (asset.extras.slicecap_gltf_versus_fit, lib/material_export's
    GltfBrdf) is what python/checks/gltf_spec_brdf.py, written separately from the Khronos texts,
    finds for the written .gltf against the fit's own table (`slicecap generate MATERIAL.json`).
    Before issue 46 they disagreed on the velvet (1.67 against 2.52: the check took the fit's
    sheen visibility) and on coloured speculars (each channel's own 1 - F)."""
    from gltf_spec_brdf import gltf_versus_fit_delta_e

    cli = find_slicecap_cli()
    fit_table = tmp_path / "fit.exr"
    subprocess.run([cli, "generate", exports[name]["json"], "-o", fit_table], check=True,
                   capture_output=True)
    gltf = exports[name]["gltf"]
    own = json.loads(gltf.read_text())["asset"]["extras"]["slicecap_gltf_versus_fit"]["delta_e"]
    assert gltf_versus_fit_delta_e(gltf, fit_table, str(cli)) == pytest.approx(own, abs=0.02)


def import_materialx():
    try:
        import MaterialX as mx
    except ImportError:
        machine = platform.machine()
        if machine not in ("x86_64", "AMD64"):
            pytest.skip(f"MaterialX has no PyPI wheel for {machine} (requirements.txt installs it "
                        "on x86_64 only)")
        pytest.skip("MaterialX is not installed (python/requirements.txt; scripts/python-env)")
    return mx


@pytest.mark.parametrize("name", MATERIALS)
def test_materialx_validates_the_document(exports, name):
    mx = import_materialx()
    import MaterialX.PyMaterialXGenGlsl as gen_glsl
    import MaterialX.PyMaterialXGenShader as gen_shader

    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(exports[name]["mtlx"]))
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    doc.setDataLibrary(library)
    valid, message = doc.validate()
    assert valid, message
    shaders = {m.getName(): [s.getCategory() for s in mx.getShaderNodes(m)]
               for m in doc.getMaterialNodes()}
    assert shaders == {"slicecap_fit": ["open_pbr_surface"],
                       "slicecap_fit_standard_surface": ["standard_surface"]}
    # Code generation resolves every node against its definition: a stricter check than validate().
    generator = gen_glsl.GlslShaderGenerator.create()
    context = gen_shader.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    for material in doc.getMaterialNodes():
        shader = generator.generate(material.getName(), material, context)
        assert shader.getSourceCode(gen_shader.PIXEL_STAGE)


def generated_lobe_tangents(mtlx: pathlib.Path) -> dict[str, list[float]]:
    """For each material of the document: the azimuths (deg, counter-clockwise from the mesh's
    tangent toward its bitangent) of the lobe axis that the GLSL MaterialX generates for it hands
    to each anisotropic BSDF, its generated code run for a fragment with normal z and tangent x
    (glsl_slice: the vertex stage's own bitangent, the surface's nodes and the shader graph's
    tangent and roughness statements). The axis is the one with the larger alpha."""
    mx = import_materialx()
    import MaterialX.PyMaterialXGenGlsl as gen_glsl
    import MaterialX.PyMaterialXGenShader as gen_shader
    from glsl_slice import bsdf_lobe_axes

    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(mtlx))
    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    doc.setDataLibrary(library)
    generator = gen_glsl.GlslShaderGenerator.create()
    context = gen_shader.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    out = {}
    for material in doc.getMaterialNodes():
        shader = generator.generate(material.getName(), material, context)
        axes = bsdf_lobe_axes(shader.getSourceCode(gen_shader.PIXEL_STAGE),
                              shader.getSourceCode(gen_shader.VERTEX_STAGE),
                              np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]))
        angles = []
        for _, tangent, roughness in axes:
            alpha_x, alpha_y = float(roughness[0]), float(roughness[1])
            if alpha_x <= alpha_y * 1.01:
                continue  # an isotropic lobe (the coat) has no direction
            angles.append(math.degrees(math.atan2(tangent[1], tangent[0])))
        out[material.getName()] = angles
    return out


def angle_difference_deg(a: float, b: float) -> float:
    """a - b for lobe axes, which repeat every 180 deg: in (-90, 90]."""
    d = (a - b) % 180.0
    return d - 180.0 if d > 90.0 else d


def export_at_tangent(cli, exports, tangent_deg: float, out: pathlib.Path) -> pathlib.Path:
    """brushed-steel-30's fit with its tangent set to `tangent_deg`, exported as .mtlx by
    `slicecap fit MATERIAL.json --mtlx`."""
    document = json.loads(exports["brushed-steel-30"]["json"].read_text())
    document["parameters"]["tangent_deg"]["value"] = tangent_deg
    material = out / f"steel-{tangent_deg:g}.json"
    material.write_text(json.dumps(document))
    mtlx = out / f"steel-{tangent_deg:g}.mtlx"
    subprocess.run([cli, "fit", material, "--mtlx", mtlx], check=True, capture_output=True)
    return mtlx


@pytest.mark.parametrize("tangent_deg", [20.0, 110.0, 135.0])
def test_materialx_generated_code_turns_the_lobe_to_the_fitted_tangent(
        exports, tmp_path, tangent_deg):
    """The lobe direction in the GLSL that MaterialX's own generator emits for the exported
    document is the fit's tangent within 1 deg, for both materials (issue 46)."""
    mtlx = export_at_tangent(find_slicecap_cli(), exports, tangent_deg, tmp_path)
    tangents = generated_lobe_tangents(mtlx)
    assert set(tangents) == {"slicecap_fit", "slicecap_fit_standard_surface"}
    for material, angles in tangents.items():
        assert angles, f"{material}: no anisotropic BSDF found in the generated code"
        for angle in angles:
            assert abs(angle_difference_deg(angle, tangent_deg)) < 1.0, (material, angle)


def test_materialx_generator_turns_rotate3d_clockwise(exports, tmp_path):
    """Why the export does not use rotate3d: the document the export wrote before (the tangent
    turned by rotate3d by +tangent_deg about the normal, standard_surface's specular_rotation =
    tangent_deg / 360) puts the lobe at -tangent_deg in MaterialX 1.39.5's generated GLSL, against
    the node's specification (counter-clockwise; AcademySoftwareFoundation/MaterialX#2083)."""
    mtlx = export_at_tangent(find_slicecap_cli(), exports, 20.0, tmp_path)
    text = mtlx.read_text()
    tangent_graph = text[text.index('  <tangent name="surface_tangent"'):
                         text.index("  <open_pbr_surface")]
    old_graph = ('  <tangent name="surface_tangent" type="vector3">\n'
                 '    <input name="space" type="string" value="world" />\n  </tangent>\n'
                 '  <normal name="surface_normal" type="vector3">\n'
                 '    <input name="space" type="string" value="world" />\n  </normal>\n'
                 '  <rotate3d name="fitted_tangent" type="vector3">\n'
                 '    <input name="in" type="vector3" nodename="surface_tangent" />\n'
                 '    <input name="amount" type="float" value="20" />\n'
                 '    <input name="axis" type="vector3" nodename="surface_normal" />\n'
                 '  </rotate3d>\n')
    old = text.replace(tangent_graph, old_graph).replace(
        '<input name="specular_rotation" type="float" value="0" />',
        '<input name="specular_rotation" type="float" value="0.0555556" />').replace(
        '    <input name="tangent" type="vector3" nodename="fitted_tangent" />\n', "")
    old_mtlx = tmp_path / "rotate3d.mtlx"
    old_mtlx.write_text(old)
    for material, angles in generated_lobe_tangents(old_mtlx).items():
        assert angles, material
        for angle in angles:
            assert abs(angle_difference_deg(angle, -20.0)) < 1.0, (material, angle)


def test_mitsuba_loads_the_snippet_matches_the_fit_and_renders(exports):
    mi = use_variant("scalar_rgb")
    files = exports["brushed-steel-30"]
    scene = mi.load_file(str(files["mitsuba"]))
    bsdf = scene.shapes()[0].bsdf()
    parameters = json.loads(files["json"].read_text())["parameters"]
    ratios = mitsuba_ratios(mi, scene, parameters)
    # Measured 2026-12-02: median 0.999, 5th percentile 0.967 (the exact Fresnel and the separable
    # Smith masking against the fit's Schlick and height-correlated Smith; grazing reflectance
    # 0.97).
    assert np.all(np.abs(np.median(ratios, axis=0) - 1) < 0.01), np.median(ratios, axis=0)
    assert np.all(np.percentile(ratios, 5, axis=0) > 0.93), np.percentile(ratios, 5, axis=0)
    assert np.all(np.percentile(ratios, 95, axis=0) < 1.03), np.percentile(ratios, 95, axis=0)

    image = render(mi, sphere_scene(mi, bsdf, size=16, spp=16))
    assert np.all(np.isfinite(image))
    assert image.mean() > 0.01


def test_mitsuba_evaluates_the_sheen_stand_in_as_exported(exports):
    """The velvet's snippet: Mitsuba's BSDF is the fit's diffuse + GGX plus the GGX stand-in for
    the sheen that the snippet's own parameters describe (so Mitsuba reads `material` "none" and
    an alpha above 1 as the exporter means), and the stand-in is really there."""
    mi = use_variant("scalar_rgb")
    files = exports["velvet-red"]
    document = json.loads(files["json"].read_text())
    assert document["model"] == "ggx+sheen"
    stand_in = sheen_stand_in(files["mitsuba"].read_text())
    assert stand_in is not None
    scene = mi.load_file(str(files["mitsuba"]))
    # A khr_materials_sheen fit's diffuse + GGX is dimmed by the extension's mean scaling.
    assert document["sheen_form"] == "khr_materials_sheen"
    rest = khr_sheen_rest_scaling(document["parameters"])
    assert rest < 0.95
    ratios = mitsuba_ratios(mi, scene, document["parameters"], extra=stand_in, rest_scale=rest)
    # Measured 2026-12-02: 1.000 at the median, 5th and 95th percentiles (velvet-red's fit had no
    # specular, so only the diffuse and the stand-in); without the stand-in, medians 1.6-3.0.
    # 2026-12-06, the khr form: velvet-red's fit has a broad lobe whose Fresnel falls from f0 0.29
    # to f90 0, which the snippet's Fresnel cannot (specular-colour-at-grazing): 95th percentile
    # up to 1.033.
    assert np.all(np.abs(np.median(ratios, axis=0) - 1) < 0.01), np.median(ratios, axis=0)
    assert np.all(np.percentile(ratios, 5, axis=0) > 0.97), np.percentile(ratios, 5, axis=0)
    assert np.all(np.percentile(ratios, 95, axis=0) < 1.05), np.percentile(ratios, 95, axis=0)
    without = mitsuba_ratios(mi, scene, document["parameters"])
    assert np.all(np.median(without, axis=0) > 1.3), np.median(without, axis=0)


def test_the_lacquer_is_fitted_with_its_coat_and_mitsuba_keeps_it(exports):
    """The coat survives the whole path: the fit finds it, and in Mitsuba's snippet (a blend with
    a dielectric GGX lobe, docs/material-export.md) the mirror reflection face on is the fit's."""
    files = exports["lacquer"]
    document = json.loads(files["json"].read_text())
    assert document["model"] == "ggx+coat", document["choice"]
    p = {k: v["value"] for k, v in document["parameters"].items()}
    assert math.isclose(p["coat_alpha"], 0.08, rel_tol=0.05)
    assert math.isclose(p["coat_weight"], 0.6, rel_tol=0.05)
    mi = use_variant("scalar_rgb")
    scene = mi.load_file(str(files["mitsuba"]))
    bsdf = scene.shapes()[0].bsdf()
    si = scene.ray_intersect(mi.Ray3f([0.01, 0.02, 1.0], [0.0, 0.0, -1.0]))
    normal = np.array([0.0, 0.0, 1.0])
    si.wi = si.to_local(mi.Vector3f(*normal))
    value = np.array(bsdf.eval(mi.BSDFContext(), si, si.to_local(mi.Vector3f(*normal))))
    # Face on, light = view = normal: the fit's base dimmed by 1 - 0.04 w, plus the coat's
    # 0.04 w D(n) / 4 with D(n) = 1 / (pi alpha^2) (G = 1 there).
    base = fitted_brdf(document["parameters"], normal, normal)
    coat = 0.04 * p["coat_weight"] / (math.pi * p["coat_alpha"] ** 2) / 4.0
    expected = base * (1.0 - 0.04 * p["coat_weight"]) + coat
    np.testing.assert_allclose(value, expected, rtol=0.03)
    assert np.all(value > 1.5 * base), "the coat's reflection is missing from the snippet"
    image = render(mi, sphere_scene(mi, bsdf, size=16, spp=16))
    assert np.all(np.isfinite(image))


def test_gltf_carries_its_measured_distance_from_the_fit(exports):
    document = json.loads(exports["brushed-steel-30"]["gltf"].read_text())
    versus = document["asset"]["extras"]["slicecap_gltf_versus_fit"]
    # GGX from GGX: the glTF lobe is the fitted one. Steel's f0 is a little coloured (0.56 / 0.57
    # / 0.58), so it goes out as the metal blend (material-export.md): 0.06 by the specification,
    # where the dielectric form is 0.01 by it and 0.06 read per channel (2026-12-06).
    assert document["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] > 0.9
    assert versus["delta_e"] < 0.1
    losses = {loss["kind"] for loss in document["asset"]["extras"]["slicecap_conversion_losses"]}
    assert "diffuse-layering" in losses
