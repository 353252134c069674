"""The consumer renders' shared scene (python/checks/consumer_scene.py): it reads the exported
glTF's sphere, refuses one without tangents by name, and gives Mitsuba a mesh whose shading
tangent is the glTF tangent turned by the fit's angle toward the bitangent (the frames of
docs/material-export.md)."""

import json
import subprocess
import sys

import numpy as np
import pytest
from conftest import REPOSITORY
from mitsuba_support import use_variant

sys.path.insert(0, str(REPOSITORY / "python" / "checks"))
import consumer_scene as cs  # noqa: E402


@pytest.fixture(scope="module")
def gltf(slicecap_cli_for_module, tmp_path_factory):
    folder = tmp_path_factory.mktemp("consumer-scene")
    table, fit, path = folder / "steel.exr", folder / "steel.json", folder / "steel.gltf"
    subprocess.run([slicecap_cli_for_module, "generate", "brushed-steel-30", "-o", table],
                   check=True, capture_output=True)
    subprocess.run([slicecap_cli_for_module, "fit", table, "-o", fit, "--gltf", path],
                   check=True, capture_output=True)
    return path


def test_reads_the_exported_sphere(gltf):
    sphere = cs.read_sphere(gltf)
    radii = np.linalg.norm(sphere.positions - sphere.centre, axis=1)
    np.testing.assert_allclose(radii, 0.5, rtol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(sphere.normals, axis=1), 1.0, rtol=1e-5)
    # Tangents lie in the surface and run along the parallels (no y component).
    assert np.max(np.abs(np.sum(sphere.normals * sphere.tangents, axis=1))) < 1e-5
    assert np.max(np.abs(sphere.tangents[:, 1])) < 1e-5


def test_a_sphere_without_tangents_is_refused_by_name(gltf, tmp_path):
    document = json.loads(gltf.read_text())
    for mesh in document["meshes"]:
        for primitive in mesh["primitives"]:
            primitive["attributes"].pop("TANGENT", None)
    broken = tmp_path / "no-tangents.gltf"
    broken.write_text(json.dumps(document))
    with pytest.raises(ValueError, match=r"no-tangents\.gltf: the sphere has no TANGENT"):
        cs.read_sphere(broken)


@pytest.mark.parametrize("angle_deg", [0.0, 30.0, 120.0])
def test_mitsuba_shading_tangent_is_the_turned_gltf_tangent(gltf, tmp_path, angle_deg):
    mi = use_variant("scalar_rgb")
    sphere = cs.read_sphere(gltf)
    ply = tmp_path / "sphere.ply"
    cs.write_ply(ply, *cs.unshared_mesh_with_tangent_uvs(sphere, angle_deg))
    scene = mi.load_dict({"type": "scene", "s": {"type": "ply", "filename": str(ply)}})
    # The expected tangent, built here independently: glTF's t turned toward n x t.
    a = np.radians(angle_deg)
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(60):
        direction = rng.normal(size=3)
        direction[2] = abs(direction[2]) + 0.3
        direction /= np.linalg.norm(direction)
        if abs(direction[1]) > 0.8:  # near the poles the parallels' direction is ill-defined
            continue
        origin = sphere.centre + 3.0 * direction
        si = scene.ray_intersect(mi.Ray3f(list(origin), list(-direction)))
        assert si.is_valid()
        n = np.array(si.sh_frame.n)
        # The parallel through the hit point, oriented as the glTF's nearest vertex tangent.
        t = np.cross([0.0, 1.0, 0.0], n)
        t /= np.linalg.norm(t)
        nearest = np.argmin(np.linalg.norm(sphere.positions - np.array(si.p), axis=1))
        t *= np.sign(t @ sphere.tangents[nearest])
        expected = np.cos(a) * t + np.sin(a) * np.cross(n, t)
        got = np.array(si.sh_frame.s)
        assert np.degrees(np.arccos(np.clip(got @ expected, -1, 1))) < 4.0
        checked += 1
    assert checked > 20


@pytest.mark.parametrize("parameters,against", [
    ({}, "snippet"),
    ({"sheen_colour": {"value": [0.3, 0.1, 0.1]}}, "tabulated fit"),
    ({"coat_weight": {"value": 0.6}, "coat_alpha": {"value": 0.05}}, "tabulated fit"),
    ({"coat_weight": {"value": 0.0}, "coat_alpha": {"value": 0.05}}, "snippet"),
], ids=["ggx", "sheen", "coat", "coat-of-weight-0"])
def test_a_fit_the_snippet_only_approximates_is_judged_against_its_tabulation(
        tmp_path, parameters, against):
    """The Mitsuba snippet approximates a sheen and a clear coat (material-export.md's
    `sheen-form`, `coat-form`): a glTF render of such a fit is judged against the tabulated fit,
    of any other fit against the snippet. The renders are told apart by their values."""
    fit = tmp_path / "m.json"
    fit.write_text(json.dumps({"parameters": {"tangent_deg": {"value": 0.0}, **parameters}}))
    for key, level in (("fit", 0.25), ("fit-tabulated", 0.5)):
        np.save(tmp_path / f"m-mitsuba-{key}.npy", np.full((4, 4, 3), level))
    image, name = cs.mitsuba_reference(str(tmp_path), {"material": "m", "exposure": 1.0},
                                       str(fit))
    assert name == against
    expected = cs.encode(np.full((4, 4, 3), 0.25 if against == "snippet" else 0.5), 1.0)
    assert np.array_equal(image, expected)
