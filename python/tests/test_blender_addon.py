"""The Blender import add-on's Blender-free half (slicecap.blender_addon): glTF's alphas mapped to
the Principled BSDF's Roughness and Anisotropic and back through Cycles' law, the clamp at ratio
10 reported, slicecap's materials found in .gltf and .glb files, and the module importing
without bpy."""

import json
import math
import struct
import subprocess
import sys

import pytest

from slicecap.blender_addon import (
    CYCLES_MAX_ALPHA_RATIO,
    blender_inputs,
    cycles_alphas,
    gltf_alphas,
    read_gltf_document,
    slicecap_materials,
)


def cycles_alphas_from_svm_closure(roughness, anisotropic):
    """Cycles' Principled BSDF as its svm_closure code writes it, independently of the module:
    aspect = sqrt(1 - 0.9 anisotropic), alpha_x = r^2 / aspect, alpha_y = r^2 aspect."""
    aspect = math.sqrt(1.0 - 0.9 * anisotropic)
    return roughness * roughness / aspect, roughness * roughness * aspect


ALPHA_PAIRS = [(alpha_b * ratio, alpha_b) for alpha_b in (0.003, 0.06, 0.09, 0.3, 0.9)
               for ratio in (1.0, 1.5, 4.0, 9.99, 10.0) if alpha_b * ratio <= 1.0]


@pytest.mark.parametrize(("alpha_t", "alpha_b"), ALPHA_PAIRS)
def test_alphas_round_trip_through_cycles_law(alpha_t, alpha_b):
    inputs = blender_inputs(alpha_t, alpha_b)
    assert 0.0 <= inputs.roughness <= 1.0 and 0.0 <= inputs.anisotropic <= 1.0
    reached = cycles_alphas_from_svm_closure(inputs.roughness, inputs.anisotropic)
    assert reached == pytest.approx((alpha_t, alpha_b), rel=0, abs=1e-9)
    assert (inputs.alpha_tangent, inputs.alpha_bitangent) == pytest.approx(reached, abs=1e-12)
    assert not inputs.clamped and inputs.loss() is None


def test_glTF_factors_round_trip_for_the_brushed_aluminium_fit():
    # roughnessFactor 0.245, anisotropyStrength 0.5554: alphas (0.35, 0.06), ratio under 10.
    alpha_t, alpha_b = gltf_alphas(0.245, 0.5554)
    assert alpha_b == pytest.approx(0.245**2)
    assert alpha_t == pytest.approx(0.245**2 + (1 - 0.245**2) * 0.5554**2)
    inputs = blender_inputs(alpha_t, alpha_b)
    assert cycles_alphas_from_svm_closure(inputs.roughness, inputs.anisotropic) == pytest.approx(
        (alpha_t, alpha_b), rel=0, abs=1e-9)
    # The importer's unchanged copy (Anisotropic = strength) renders a shorter lobe.
    assert cycles_alphas(0.245, 0.5554)[0] < 0.5 * alpha_t


def test_isotropic_stays_isotropic():
    for alpha in (0.0, 0.01, 0.2, 1.0):
        inputs = blender_inputs(alpha, alpha)
        assert inputs.anisotropic == 0.0
        assert inputs.roughness == pytest.approx(math.sqrt(alpha), abs=1e-12)
        assert not inputs.clamped
    assert gltf_alphas(0.4, 0.0) == pytest.approx((0.16, 0.16))


def test_ratio_20_is_clamped_and_reported():
    inputs = blender_inputs(0.4, 0.02)
    assert inputs.clamped and inputs.anisotropic == 1.0
    reached = cycles_alphas_from_svm_closure(inputs.roughness, inputs.anisotropic)
    assert reached[0] / reached[1] == pytest.approx(CYCLES_MAX_ALPHA_RATIO, abs=1e-9)
    # The geometric mean is kept, so neither alpha is what glTF asked.
    assert reached[0] * reached[1] == pytest.approx(0.4 * 0.02, abs=1e-12)
    assert reached[0] < 0.4 and reached[1] > 0.02
    loss = inputs.loss()
    assert loss is not None and "ratio 20" in loss and "maximum 10" in loss


def test_bad_values_are_refused_by_name():
    with pytest.raises(ValueError, match="roughnessFactor"):
        gltf_alphas(1.5, 0.2)
    with pytest.raises(ValueError, match="anisotropyStrength"):
        gltf_alphas(0.5, -0.1)
    with pytest.raises(ValueError, match="below alpha_bitangent"):
        blender_inputs(0.1, 0.2)


def slicecap_document(generator="slicecap 0.9.0", name="slicecap-fit"):
    return {"asset": {"version": "2.0", "generator": generator},
            "materials": [{"name": name, "pbrMetallicRoughness": {"roughnessFactor": 0.3},
                           "extensions": {"KHR_materials_anisotropy": {
                               "anisotropyStrength": 0.6, "anisotropyRotation": 1.0}}}]}


def test_finds_slicecap_material_in_gltf_and_glb(tmp_path):
    document = slicecap_document()
    gltf = tmp_path / "m.gltf"
    gltf.write_text(json.dumps(document))
    chunk = json.dumps(document).encode()
    chunk += b" " * (-len(chunk) % 4)
    glb = tmp_path / "m.glb"
    glb.write_bytes(struct.pack("<4sII", b"glTF", 2, 20 + len(chunk))
                    + struct.pack("<I4s", len(chunk), b"JSON") + chunk)
    for path in (gltf, glb):
        (material,) = slicecap_materials(read_gltf_document(path))
        assert (material.roughness_factor, material.anisotropy_strength,
                material.anisotropy_rotation_rad, material.textured) == (0.3, 0.6, 1.0, False)


def test_other_files_have_no_slicecap_material(tmp_path):
    assert slicecap_materials(slicecap_document(generator="Khronos glTF Blender I/O")) == []
    assert slicecap_materials(slicecap_document(name="paint")) == []
    bad = tmp_path / "bad.gltf"
    bad.write_text("not json")
    with pytest.raises(ValueError, match="bad.gltf"):
        read_gltf_document(bad)


def test_module_imports_without_bpy():
    # A fresh interpreter in which `import bpy` fails, as outside Blender.
    code = ("import sys; sys.modules['bpy'] = None; import slicecap.blender_addon as a; "
            "assert a.bl_info['blender'] >= (4, 1, 0); print(a.blender_inputs(0.2, 0.1).roughness)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert float(result.stdout) == pytest.approx(0.02**0.25)
