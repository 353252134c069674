"""The material viewer page (python -m slicecap.viewer, docs/material-viewer.md): self-contained,
well-formed, carrying the table and the fit's parameters; its shader's fitted BRDF, run in Python
from the page's own GLSL text, is lib/fit's model; bad input is refused naming the file. The real
browser's rendering is checked by scripts/consumer-check (section viewer), not here."""

import base64
import dataclasses
import html.parser
import json
import math
import re
import shutil
import subprocess

import numpy as np
import pytest
from brdf_pairs import random_pairs
from conftest import find_slicecap_cli

from slicecap import viewer, viewer_scene
from slicecap.abrdf_exr import write_abrdf_exr
from slicecap.fitted_material import (
    SHEEN_ALBEDO_MAX_ROUGHNESS,
    SHEEN_ALBEDO_MIN_ROUGHNESS,
    FittedMaterial,
    ggx_lobe,
    has_coat,
    has_sheen,
    read_fitted_material,
    sheen_albedo_table,
)
from slicecap.grid import GRID_DIRECTIONS_DEG, tabulate
from slicecap.render import render_sphere_point_light

STEEL = FittedMaterial("ggx", (0.03, 0.03, 0.03), (0.56, 0.57, 0.58), 1.0, 0.4, 0.1, 120.0)
VELVET = FittedMaterial(
    "ggx+sheen", (0.15, 0.01, 0.02), (0.02, 0.03, 0.04), 0.4, 0.3, 0.12, 37.0,
    sheen_colour=(0.7, 0.15, 0.15), sheen_roughness=0.3, sheen_form="additive",
)
# A rough anisotropic red base under a sharper coat, and the velvet under a rough half-weight coat:
# the coat's lobe, its view-angle Fresnel and its dimming of everything beneath, sheen included.
COATED_STEEL = FittedMaterial(
    "ggx+coat", (0.2, 0.02, 0.02), (0.5, 0.1, 0.1), 0.8, 0.45, 0.2, 70.0,
    coat_weight=0.9, coat_alpha=0.05,
)
COATED_VELVET = FittedMaterial(
    "ggx+sheen+coat", (0.15, 0.01, 0.02), (0.02, 0.03, 0.04), 0.4, 0.3, 0.12, 37.0,
    sheen_colour=(0.7, 0.15, 0.15), sheen_roughness=0.3, coat_weight=0.5, coat_alpha=0.3,
    sheen_form="additive",
)
# The same two in KHR_materials_sheen's form (format version 2's fits).
KHR_VELVET = dataclasses.replace(VELVET, sheen_form="khr_materials_sheen")
KHR_COATED_VELVET = dataclasses.replace(COATED_VELVET, sheen_form="khr_materials_sheen")


def fit_document(material: FittedMaterial) -> dict:
    """A `slicecap fit` JSON as docs/material-fit.md describes it (the fields the viewer reads)."""
    # Written as format version 1, whose sheen is the additive one (the materials above).
    names = [n for n in FittedMaterial.__dataclass_fields__ if n not in ("model", "sheen_form")]
    if not has_sheen(material.model):
        names = [n for n in names if not n.startswith("sheen")]
    if not has_coat(material.model):
        names = [n for n in names if not n.startswith("coat")]
    parameters = {}
    for name in names:
        value = getattr(material, name)
        parameters[name] = {"value": list(value) if isinstance(value, tuple) else value,
                            "sigma": None, "unit": "-"}
    return {"format": "slicecap-material", "format_version": 1, "source": "t.exr",
            "model": material.model, "parameters": parameters, "metrics": {"delta_e": 0.0}}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    root = tmp_path_factory.mktemp("viewer")
    table = root / "velvet.exr"
    write_abrdf_exr(table, tabulate(VELVET.evaluate))
    fit = root / "velvet.json"
    fit.write_text(json.dumps(fit_document(VELVET)))
    return {"root": root, "table": table, "fit": fit}


@pytest.fixture(scope="module")
def page(files):
    output = files["root"] / "view.html"
    assert viewer.run([str(files["table"]), "--material", str(files["fit"]), "-o", str(output),
                       "--panel-size", "128"]) == 0
    return output.read_text(encoding="utf-8")


class _Collector(html.parser.HTMLParser):
    """Tags, their attributes and the text of each script element, by id."""

    VOID = {"meta", "input", "img", "br", "link"}

    def __init__(self):
        super().__init__()
        self.attributes, self.scripts, self.open = [], {}, []
        self._script = None

    def handle_starttag(self, tag, attrs):
        self.attributes += [(tag, name, value) for name, value in attrs]
        if tag not in self.VOID:
            self.open.append(tag)
        if tag == "script":
            self._script = dict(attrs).get("id", f"inline-{len(self.scripts)}")
            self.scripts[self._script] = ""

    def handle_endtag(self, tag):
        assert self.open and self.open[-1] == tag, f"</{tag}> closes <{self.open[-1:]}>"
        self.open.pop()
        self._script = None

    def handle_data(self, data):
        if self._script is not None:
            self.scripts[self._script] += data


def parse(page: str) -> _Collector:
    collector = _Collector()
    collector.feed(page)
    collector.close()
    assert collector.open == [], f"unclosed elements: {collector.open}"
    return collector


def page_data(page: str) -> dict:
    return json.loads(parse(page).scripts["slicecap-data"])


def test_page_is_self_contained_and_well_formed(page):
    parsed = parse(page)
    links = [(tag, name, value) for tag, name, value in parsed.attributes
             if name in ("src", "href")]
    assert links, "the layout picture's src is expected"
    for tag, name, value in links:
        assert value.startswith("data:"), f"<{tag} {name}={value[:60]!r}> is not inline"
    # No URL at all: nothing the page could fetch, in a script or a style either.
    assert not re.search(r"https?://|//cdn|@import", page)
    assert "{{" not in page, "a template placeholder was left"
    assert {"slicecap-data", "vertex-shader", "fragment-shader"} <= set(parsed.scripts)


def test_page_embeds_the_table_the_parameters_and_the_layout_picture(page, files):
    data = page_data(page)
    from slicecap.abrdf_exr import read_abrdf_exr

    table = read_abrdf_exr(files["table"]).values
    embedded = np.frombuffer(base64.b64decode(data["table"]["values_base64"]), dtype="<f4")
    assert np.array_equal(embedded.reshape(81, 81, 3), table)
    parameters = data["material"]["parameters"]
    assert data["material"]["model"] == "ggx+sheen"
    for name in ("diffuse_albedo", "specular_f0", "sheen_colour"):
        assert parameters[name] == list(getattr(VELVET, name))
    for name in ("specular_f90", "alpha_tangent", "alpha_bitangent", "tangent_deg"):
        assert parameters[name] == getattr(VELVET, name)
    albedo = np.frombuffer(base64.b64decode(data["material"]["albedo_base64"]), dtype="<f4")
    assert albedo.shape == (243,) and np.all(albedo > 0)
    uri = re.search(r'<img id="layout"[^>]*src="data:image/png;base64,([^"]+)"', page).group(1)
    png = base64.b64decode(uri)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert int.from_bytes(png[16:20], "big") == 81 * viewer.LAYOUT_SCALE + 5
    assert data["exposure"] > 0 and data["panel_size"] == 128


@pytest.mark.parametrize("material", [COATED_STEEL, COATED_VELVET], ids=["ggx+coat",
                                                                         "ggx+sheen+coat"])
def test_coat_page_lists_the_coat_and_its_environment_includes_it(files, tmp_path, material):
    fit = tmp_path / "coat.json"
    fit.write_text(json.dumps(fit_document(material)))
    output = tmp_path / "coat.html"
    assert viewer.run([str(files["table"]), "--material", str(fit), "-o", str(output),
                       "--panel-size", "64"]) == 0
    page = output.read_text(encoding="utf-8")
    data = page_data(page)["material"]
    assert data["model"] == material.model
    for name in ("coat_weight", "coat_alpha"):
        assert data["parameters"][name] == getattr(material, name)
        assert f"<td>{name}</td><td>{getattr(material, name):.4g}</td>" in page
    # The environment term is the coated BRDF's albedo. At a fixed view the coat's Fresnel Fc is a
    # constant, so that albedo is (1 - w Fc) x the base's + w Fc x the coat lobe's, each
    # integrated alone.
    albedo = np.frombuffer(base64.b64decode(data["albedo_base64"]), dtype="<f4").reshape(81, 3)
    base = dataclasses.replace(material, model=material.model.removesuffix("+coat"))
    base_albedo = viewer_scene.directional_albedo(base.evaluate)

    def coat_lobe(light, view):
        half = (light + view) / np.linalg.norm(light + view, axis=-1, keepdims=True)
        lobe = ggx_lobe(light, view, half, material.coat_alpha, material.coat_alpha, 0.0)
        return np.repeat(lobe[:, None], 3, axis=1)

    coat_albedo = viewer_scene.directional_albedo(coat_lobe)
    cos_v = np.cos(np.radians(GRID_DIRECTIONS_DEG[:, 0]))[:, None]
    weighted_fresnel = material.coat_weight * (0.04 + 0.96 * (1.0 - cos_v) ** 5)
    expected = (1.0 - weighted_fresnel) * base_albedo + weighted_fresnel * coat_albedo
    np.testing.assert_allclose(albedo, expected, rtol=1e-5)
    assert np.max(np.abs(albedo / base_albedo - 1.0)) > 0.05, "the coat must show in the albedo"


def test_page_script_is_valid_javascript(page, tmp_path):
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed (scripts/deps/host.txt: nodejs)")
    scripts = [s for k, s in parse(page).scripts.items() if k.startswith("inline")]
    assert len(scripts) == 1
    path = tmp_path / "page.js"
    path.write_text(scripts[0])
    run = subprocess.run([node, "--check", path], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_layout_picture_is_light_rows_by_view_columns():
    values = np.zeros((81, 81, 3), dtype=np.float32)
    values[3, 40] = (2.0, 1.0, 0.0)  # light 3 (15 deg ring), view 40 (60 deg ring)
    values[70, 5] = (0.02, 0.02, 0.02)
    image = viewer.layout_picture(values)
    scale = viewer.LAYOUT_SCALE
    assert image.shape == (81 * scale + 5,) * 2 + (3,)
    y, x = viewer.layout_offset(3), viewer.layout_offset(40)
    assert (y, x) == (3 * scale + 1, 40 * scale + 4)  # one ring line above, four to the left
    assert image[y : y + scale, x : x + scale].tolist() == [[[255, 188, 0]] * scale] * scale
    assert image[viewer.layout_offset(1) - 1, x].tolist() == [72, 72, 72]  # rings 0 / 1
    # A dim entry on the 75 deg light ring: 0.02 cos(75) / (2 cos(15)), sRGB, x255.
    dim = image[viewer.layout_offset(70), viewer.layout_offset(5)]
    assert dim.tolist() == [int(np.floor(255 * 1.055 * (0.02 * np.cos(np.radians(75)) / (
        2 * np.cos(np.radians(15)))) ** (1 / 2.4) - 255 * 0.055 + 0.5))] * 3
    assert image[viewer.layout_offset(40), viewer.layout_offset(3)].tolist() == [0, 0, 0]


# ---- the shader's fittedBrdf, run from the page's GLSL text ----

class _Vec(np.ndarray):
    x = property(lambda self: self[0])
    y = property(lambda self: self[1])
    z = property(lambda self: self[2])


def _vec(*components):
    return np.array(components, dtype=np.float64).view(_Vec)


class _Texel:
    """A one-channel texel, read as .r."""

    def __init__(self, value):
        self.r = float(value)


def _normalize(v):
    return (v / np.linalg.norm(v)).view(_Vec)


def glsl_function(page: str, name: str, uniforms: dict):
    """The GLSL code between "// BEGIN name" and "// END name" in the page, transliterated to
    Python (functions of vec3 or float, their statements one a line: declarations, assignments,
    if blocks, return), and its function `name`."""
    source = parse(page).scripts["fragment-shader"]
    body = re.search(rf"// BEGIN {name}.*?\n((?:vec3|float) .*?)// END {name}", source,
                     re.S).group(1)
    lines, depth = [], 0
    for raw in body.splitlines():
        line = raw.split("//")[0].strip()
        if not line:
            continue
        if line == "}":
            depth -= 1
            continue
        match = re.match(r"(?:vec3|float) (\w+)\((.*)\) \{$", line)
        if match:
            params = ", ".join(p.split()[-1] for p in match.group(2).split(","))
            lines.append(f"def {match.group(1)}({params}):")
            depth = 1
            continue
        match = re.match(r"if \((.*)\) \{$", line)
        if match:
            lines.append("    " * depth + f"if {match.group(1)}:")
            depth += 1
            continue
        line = re.sub(r"^(vec2|vec3|float|int) ", "", line).rstrip(";")
        lines.append("    " * depth + line)
    namespace = {
        "vec2": _vec, "vec3": _vec, "normalize": _normalize, "cos": math.cos, "sin": math.sin,
        "sqrt": np.sqrt, "log": np.log, "exp": np.exp, "max": np.maximum, "dot": np.dot,
        "clamp": np.clip, "pow": np.power, "floor": math.floor,
        "mix": lambda a, b, t: a * (1.0 - t) + b * t,
        # A sampler is its (rows, columns) array; ivec2(x, y) its column x, row y.
        "ivec2": lambda x, y: (int(x), int(y)),
        "texelFetch": lambda table, at, lod: _Texel(table[at[1], at[0]]),
        "PI": 3.14159265358979, **uniforms,
    }
    exec("\n".join(lines), namespace)
    return namespace[name]


def shader_uniforms(material: FittedMaterial) -> dict:
    """The values the shader's useFitUniforms copies from the uniforms viewer_page.js sets."""
    return {
        "m_diffuse": np.array(material.diffuse_albedo), "m_f0": np.array(material.specular_f0),
        "m_f90": material.specular_f90, "m_alphaT": material.alpha_tangent,
        "m_alphaB": material.alpha_bitangent, "m_tangentRad": math.radians(material.tangent_deg),
        "m_sheen": 1 if has_sheen(material.model) else 0,
        "m_sheenColour": _vec(*material.sheen_colour),
        "m_sheenRoughness": material.sheen_roughness,
        "m_sheenKhr": 1 if material.sheen_form == "khr_materials_sheen" else 0,
        # The albedo table viewer.sheen_albedo_data embeds in the page (there as float32; here
        # float64, so that the comparison is of the formulas alone).
        "u_sheenAlbedo": sheen_albedo_table(),
        "u_sheenAlbedoNodes": np.array(sheen_albedo_table().shape[::-1]).view(_Vec),
        "u_sheenAlbedoRoughness": _vec(SHEEN_ALBEDO_MIN_ROUGHNESS, SHEEN_ALBEDO_MAX_ROUGHNESS),
        "m_coat": 1 if has_coat(material.model) else 0,
        "m_coatWeight": material.coat_weight, "m_coatAlpha": material.coat_alpha,
    }


@pytest.mark.parametrize(
    "material", [STEEL, VELVET, COATED_STEEL, COATED_VELVET, KHR_VELVET, KHR_COATED_VELVET],
    ids=["ggx", "ggx+sheen", "ggx+coat", "ggx+sheen+coat", "ggx+sheen khr",
         "ggx+sheen+coat khr"])
def test_shader_brdf_is_the_fit_model(page, material):
    shader = glsl_function(page, "fittedBrdf", shader_uniforms(material))
    lights, views = random_pairs(200, seed=3)
    expected = material.evaluate(lights, views)
    for light, view, value in zip(lights, views, expected, strict=True):
        got = shader(_vec(*light), _vec(*view))
        np.testing.assert_allclose(got, value, rtol=1e-9, atol=1e-12)


def test_shader_port_would_see_a_wrong_tangent(page):
    """The comparison above can fail: the tangent's sign flipped gives other values."""
    uniforms = shader_uniforms(STEEL)
    uniforms["m_tangentRad"] = -uniforms["m_tangentRad"]
    shader = glsl_function(page, "fittedBrdf", uniforms)
    lights, views = random_pairs(50, seed=4)
    got = np.array(
        [shader(_vec(*lt), _vec(*vw)) for lt, vw in zip(lights, views, strict=True)]
    )
    assert np.max(np.abs(got / STEEL.evaluate(lights, views) - 1)) > 0.1


@pytest.mark.parametrize("material", [KHR_VELVET, VELVET], ids=["khr", "additive"])
def test_shader_port_would_see_the_other_sheen_form(page, material):
    """A shader drawing one sheen form for the other gives other values: the comparison above
    tells the forms apart."""
    uniforms = shader_uniforms(material)
    uniforms["m_sheenKhr"] = 1 - uniforms["m_sheenKhr"]
    shader = glsl_function(page, "fittedBrdf", uniforms)
    lights, views = random_pairs(50, seed=5)
    got = np.array(
        [shader(_vec(*lt), _vec(*vw)) for lt, vw in zip(lights, views, strict=True)]
    )
    assert np.max(np.abs(got / material.evaluate(lights, views) - 1)) > 0.1


def test_khr_sheen_page_carries_the_albedo_table(files, tmp_path, page):
    """A version-2 khr_materials_sheen fit's page embeds lib/fit's E table for the shader's
    scaling (float32) and says its form; a version-1 fit's (additive) carries none."""
    fit = tmp_path / "khr.json"
    fit.write_text(json.dumps(fit_document(KHR_VELVET)
                              | {"format_version": 2, "sheen_form": "khr_materials_sheen"}))
    output = tmp_path / "khr.html"
    assert viewer.run([str(files["table"]), "--material", str(fit), "-o", str(output),
                       "--panel-size", "64"]) == 0
    text = output.read_text(encoding="utf-8")
    albedo = page_data(text)["material"]["sheen_albedo"]
    table = sheen_albedo_table()
    assert (albedo["roughnesses"], albedo["cosines"]) == table.shape
    assert (albedo["min_roughness"], albedo["max_roughness"]) == (
        SHEEN_ALBEDO_MIN_ROUGHNESS, SHEEN_ALBEDO_MAX_ROUGHNESS)
    embedded = np.frombuffer(base64.b64decode(albedo["base64"]), dtype="<f4").reshape(table.shape)
    np.testing.assert_array_equal(embedded, table.astype(np.float32))
    assert "<td>sheen_form</td><td>khr_materials_sheen</td>" in text
    assert "sheen_albedo" not in page_data(page)["material"]
    assert "<td>sheen_form</td><td>additive</td>" in page


# ---- the numpy reference of lib/fit's model, against the C++ tables ----

@pytest.mark.parametrize(
    "name,material",
    [
        ("brushed-steel-30", FittedMaterial("ggx", (0.03,) * 3, (0.56, 0.57, 0.58), 1.0, 0.1, 0.4,
                                            30.0)),
        ("velvet-red", FittedMaterial("ggx+sheen", (0.15, 0.01, 0.02), (0.0,) * 3, 0.0, 0.3, 0.3,
                                      0.0, sheen_colour=(0.7, 0.15, 0.15), sheen_roughness=0.3,
                                      sheen_form="additive")),
    ],
)
def test_numpy_model_matches_the_cpp_built_in_tables(tmp_path, name, material):
    """The built-in GGX and sheen (`slicecap generate`) are the fit model's lobes (material-fit.md:
    with f90 = 1 the model is the built-in GGX), so the port tabulates to the C++ table."""
    cli = find_slicecap_cli()
    path = tmp_path / f"{name}.exr"
    subprocess.run([cli, "generate", name, "-o", path], check=True, capture_output=True)
    from slicecap.abrdf_exr import read_abrdf_exr

    np.testing.assert_allclose(tabulate(material.evaluate), read_abrdf_exr(path).values,
                               rtol=2e-5, atol=1e-7)


def test_cpp_fit_json_reads_and_reproduces_its_table(tmp_path):
    cli = find_slicecap_cli()
    table, fit = tmp_path / "steel.exr", tmp_path / "steel.json"
    subprocess.run([cli, "generate", "brushed-steel-30", "-o", table], check=True,
                   capture_output=True)
    subprocess.run([cli, "fit", table, "-o", fit], check=True, capture_output=True)
    material = read_fitted_material(fit)
    from slicecap.abrdf_exr import read_abrdf_exr

    values = read_abrdf_exr(table).values
    relative = np.linalg.norm(tabulate(material.evaluate) - values) / np.linalg.norm(values)
    assert relative < 1e-3


@pytest.mark.parametrize("material", [COATED_STEEL, COATED_VELVET],
                         ids=["ggx+coat", "ggx+sheen+coat"])
def test_numpy_coat_matches_slicecap_generate_of_its_json(tmp_path, material):
    """`slicecap generate FIT.json` tabulates a fit with lib/fit's own evaluation: the port's coat
    (and the sheen beneath it) must tabulate to the same table."""
    cli = find_slicecap_cli()
    fit, table = tmp_path / "coat.json", tmp_path / "coat.f32"
    fit.write_text(json.dumps(fit_document(material)))
    subprocess.run([cli, "generate", fit, "-o", table], check=True, capture_output=True)
    reference = np.fromfile(table, dtype="<f4").reshape(81, 81, 3)
    np.testing.assert_allclose(tabulate(material.evaluate), reference, rtol=2e-5, atol=1e-7)


@pytest.mark.parametrize("model", ["ggx+sheen", "ggx+sheen+coat"])
def test_numpy_khr_sheen_matches_slicecap_generate_of_its_version_2_json(tmp_path, model):
    """Format version 2's "khr_materials_sheen" form: the port's Charlie visibility and albedo
    table tabulate to lib/fit's, and a version-1 file of the same parameters (additive) does not."""
    cli = find_slicecap_cli()
    material = FittedMaterial(**{**COATED_VELVET.__dict__, "model": model,
                                 "sheen_form": "khr_materials_sheen"})
    document = fit_document(material) | {"format_version": 2, "sheen_form": "khr_materials_sheen"}
    fit, table = tmp_path / "khr.json", tmp_path / "khr.f32"
    fit.write_text(json.dumps(document))
    subprocess.run([cli, "generate", fit, "-o", table], check=True, capture_output=True)
    reference = np.fromfile(table, dtype="<f4").reshape(81, 81, 3)
    np.testing.assert_allclose(tabulate(material.evaluate), reference, rtol=2e-5, atol=1e-7)
    additive = FittedMaterial(**{**material.__dict__, "sheen_form": "additive"})
    assert np.max(np.abs(tabulate(additive.evaluate) / reference - 1)) > 0.01


def test_cpp_fit_of_a_coated_table_reads_as_a_coat_and_reproduces_it(tmp_path):
    """A table of a round red lobe under a sharp coat, tabulated by the port: `slicecap fit`
    chooses the coat, and its JSON, read back, gives the table again (the fields' names and
    meaning agree both ways)."""
    cli = find_slicecap_cli()
    truth = FittedMaterial("ggx+coat", (0.2, 0.02, 0.02), (0.5, 0.1, 0.1), 0.8, 0.3, 0.3, 0.0,
                           coat_weight=0.9, coat_alpha=0.05)
    table, fit = tmp_path / "coated.exr", tmp_path / "coated.json"
    write_abrdf_exr(table, tabulate(truth.evaluate))
    subprocess.run([cli, "fit", table, "-o", fit], check=True, capture_output=True)
    material = read_fitted_material(fit)
    assert material.model == "ggx+coat"
    values = tabulate(truth.evaluate)
    relative = np.linalg.norm(tabulate(material.evaluate) - values) / np.linalg.norm(values)
    assert relative < 1e-3


# ---- the scene's numpy renderer ----

def test_sphere_renderer_gives_lambert_radiance():
    albedo = 0.6

    def brdf(light: np.ndarray, view: np.ndarray) -> np.ndarray:
        return np.full(light.shape, albedo / np.pi)

    albedo81 = viewer_scene.directional_albedo(brdf)
    np.testing.assert_allclose(albedo81, albedo, rtol=2e-3)
    size = 65  # an odd size: the middle pixel looks at the sphere's front point (0, 0, 1)
    image, mask = render_sphere_point_light(brdf, albedo81, size, 0.0, 0.0, 0.0, 0.0, env=0.25)
    point = np.array([0.0, 0.0, 1.0])
    to_light = viewer_scene.LIGHT_DISTANCE * viewer_scene.orbit_direction(0.0, 0.0) - point
    expected = albedo / np.pi * viewer_scene.LIGHT_INTENSITY / (to_light @ to_light) + 0.25 * albedo
    np.testing.assert_allclose(image[size // 2, size // 2], expected, rtol=3e-3)
    assert mask[size // 2, size // 2] and not mask[0, 0]


# ---- bad input ----

def test_not_a_table_is_refused_naming_it(tmp_path, capsys, files):
    bogus = tmp_path / "notes.exr"
    bogus.write_text("not an EXR")
    output = tmp_path / "view.html"
    assert viewer.run([str(bogus), "--material", str(files["fit"]), "-o", str(output)]) == 1
    assert f"slicecap.viewer: {bogus}: cannot read EXR" in capsys.readouterr().err
    assert not output.exists()


def test_all_zero_table_is_refused_naming_it(tmp_path, capsys):
    table = tmp_path / "black.exr"
    write_abrdf_exr(table, np.zeros((81, 81, 3), dtype=np.float32))
    output = tmp_path / "view.html"
    assert viewer.run([str(table), "-o", str(output)]) == 1
    assert f"slicecap.viewer: {table}: the table has no positive value" in capsys.readouterr().err
    assert not output.exists()


@pytest.mark.parametrize(
    "content,message",
    [
        ("{", "not JSON"),
        ('{"format": "something-else"}', 'not a completed slicecap fit: "format"'),
        (json.dumps({**fit_document(STEEL), "model": "ward"}), '"model" \'ward\''),
        (json.dumps({**fit_document(STEEL), "parameters": {}}),
         "parameter diffuse_albedo is missing"),
        (json.dumps(fit_document(STEEL)).replace('"value": 0.4', '"value": null'),
         "parameter alpha_tangent must be a finite number"),
        (json.dumps(fit_document(STEEL)).replace('"value": 0.1', '"value": -0.1'),
         "parameter alpha_bitangent must be positive"),
        (json.dumps({**fit_document(STEEL), "metrics": {}}), "a fit that did not finish"),
        (json.dumps(fit_document(STEEL)).replace('"value": 1.0', '"value": 1.5'),
         "parameter specular_f90 must be in [0, 1]"),
        (json.dumps(fit_document(COATED_STEEL)).replace('"value": 0.9', '"value": 1.9'),
         "parameter coat_weight must be in [0, 1]"),
        (json.dumps({**fit_document(STEEL), "model": "ggx+coat"}),
         "parameter coat_weight is missing"),
    ],
    ids=["not-json", "format", "model", "no-parameters", "null-alpha", "negative-alpha",
         "unfinished", "f90-range", "coat-weight-range", "coat-missing"],
)
def test_not_a_completed_fit_is_refused_naming_it(tmp_path, capsys, files, content, message):
    bogus = tmp_path / "material.json"
    bogus.write_text(content)
    output = tmp_path / "view.html"
    assert viewer.run([str(files["table"]), "--material", str(bogus), "-o", str(output)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"slicecap.viewer: {bogus}: ") and message in err, err
    assert not output.exists()


def test_page_without_a_fit_shows_the_table(files, tmp_path):
    output = tmp_path / "table-only.html"
    assert viewer.run([str(files["table"]), "-o", str(output)]) == 0
    page = output.read_text(encoding="utf-8")
    assert page_data(page)["material"] is None and "no fit given" in page


def test_output_naming_an_input_is_bad_usage(files, capsys):
    assert viewer.run([str(files["table"]), "-o", str(files["table"])]) == 2
    assert "would be overwritten" in capsys.readouterr().err
