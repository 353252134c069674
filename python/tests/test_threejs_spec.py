"""slicecap's threejs_spec.js (python/src/slicecap): three.js 0.187's shader chunks with the
direct light drawn by the glTF specification. Run under Node with the pinned three.js
(tools/consumers, scripts/consumers-install); the renders themselves are the consumer check's
(scripts/consumer-check threejs)."""

import json
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

from slicecap.fitted_material import (
    SHEEN_ALBEDO_COSINES,
    SHEEN_ALBEDO_MAX_ROUGHNESS,
    SHEEN_ALBEDO_MIN_ROUGHNESS,
    SHEEN_ALBEDO_ROUGHNESSES,
    sheen_albedo,
)

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
THREE = REPOSITORY / "tools" / "consumers" / "node_modules" / "three" / "build" / "three.module.js"
MODULE = REPOSITORY / "python" / "src" / "slicecap" / "threejs_spec.js"
# A node of the albedo table's roughness axis, where its interpolation returns the node itself.
ALPHA_NODE = SHEEN_ALBEDO_MIN_ROUGHNESS + 10 * (
    (SHEEN_ALBEDO_MAX_ROUGHNESS - SHEEN_ALBEDO_MIN_ROUGHNESS) / (SHEEN_ALBEDO_ROUGHNESSES - 1))


def run_node(tmp_path: pathlib.Path, body: str):
    node = shutil.which("node")
    if node is None or not THREE.is_file():
        pytest.skip("three.js is not installed (node and scripts/consumers-install)")
    # Node reads a .js file outside a "type": "module" package as CommonJS unless it detects ES
    # syntax itself, which Debian 12's Node 18 does not (a fresh Debian root failed here with
    # "Unexpected token 'export'"); browsers load it as the module it is. A copy named .mjs is
    # read as an ES module by every Node.
    module = tmp_path / "threejs_spec.mjs"
    shutil.copyfile(MODULE, module)
    script = tmp_path / "run.mjs"
    script.write_text(f"import * as THREE from '{THREE.as_uri()}';\n"
                      f"import * as spec from '{module.as_uri()}';\n{body}\n")
    run = subprocess.run([node, script], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def test_the_four_lines_are_replaced_in_the_pinned_three(tmp_path):
    chunks = run_node(tmp_path, "console.log(JSON.stringify("
                                "spec.specificationChunks(THREE.ShaderChunk, THREE.REVISION)));")
    pars, begin = chunks["lights_physical_pars_fragment"], chunks["lights_fragment_begin"]
    assert "float V = V_Charlie( dotNV, dotNL, sheenRoughness );" in pars
    assert "V_Neubelt( dotNV, dotNL );" not in pars
    assert pars.count("slicecapSheenAlbedoAt( dot( geometryNormal,") == 2
    assert "IBLSheenBRDF( geometryNormal, directLight.direction" not in pars
    assert "diffuseBRDF * ( 1.0 - max3( F ) );" in pars
    assert "material.multiScatteringCompensation = vec3( 1.0 );" in begin


def test_a_three_without_a_replaced_line_is_refused_naming_it(tmp_path):
    result = run_node(tmp_path, """
const chunks = { ...THREE.ShaderChunk,
  lights_fragment_begin: THREE.ShaderChunk.lights_fragment_begin.replace('EssMs - 1.0', 'EssMs') };
try { spec.specificationChunks(chunks, 'changed'); console.log(JSON.stringify(null)); }
catch (e) { console.log(JSON.stringify(String(e.message))); }""")
    assert result is not None and "lights_fragment_begin" in result and "changed" in result


def test_the_sheen_albedo_is_the_fits_own(tmp_path):
    """The E the direct light's albedo scaling takes is the fit's and the specification's
    evaluators' (fitted_material.sheen_albedo_table, the same quadrature), not three.js's curve
    fit IBLSheenBRDF, which is 10-60 % away from it for these roughnesses."""
    albedo = np.array(run_node(tmp_path, f"console.log(JSON.stringify(Array.from("
                                         f"spec.sheenAlbedo({ALPHA_NODE!r}))));"))
    cosines = np.linspace(0.0, 1.0, SHEEN_ALBEDO_COSINES)
    np.testing.assert_allclose(albedo, sheen_albedo(cosines, ALPHA_NODE), rtol=1e-5)


def test_the_parts_can_be_made_one_at_a_time(tmp_path):
    """For the split by cause (python/checks/threejs_render_split.py): only the named part's
    lines change."""
    chunks = run_node(tmp_path, "console.log(JSON.stringify(spec.specificationChunks("
                                "THREE.ShaderChunk, THREE.REVISION, ['multiscatter'])));")
    assert "V_Neubelt( dotNV, dotNL );" in chunks["lights_physical_pars_fragment"]
    assert "diffuseBRDF * ( 1.0 - F );" in chunks["lights_physical_pars_fragment"]
    assert "multiScatteringCompensation = vec3( 1.0 );" in chunks["lights_fragment_begin"]
