"""three.js 0.187's BRDF of a glTF material under one point light, in numpy, term for term as its
WebGL shader chunks draw it (tools/consumers/node_modules/three, src/renderers/shaders/ShaderChunk:
lights_physical_fragment.glsl.js sets the material, lights_fragment_begin.glsl.js its
multiple-scattering compensation, lights_physical_pars_fragment.glsl.js RE_Direct_Physical,
BRDF_GGX, BRDF_Sheen, D_Charlie, V_Neubelt and IBLSheenBRDF; common.glsl.js F_Schlick), with the
factors GLTFLoader (examples/jsm/loaders/GLTFLoader.js) gives MeshPhysicalMaterial.

Each place where three.js departs from the Khronos texts (python/checks/gltf_spec_brdf.py) is a
switch, so that a figure can be split by cause; with every switch on the specification's side the
function equals gltf_spec_brdf.gltf_brdf (Charlie visibility) up to the sheen albedo's
quadrature. Used by threejs_spec_split.py.

    DEVIATIONS = ("visibility", "sheen_albedo", "diffuse_dimming", "multiscatter", "fresnel",
                  "charlie_floor")
"""

import pathlib
import re
import sys

import numpy as np

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPOSITORY / "python" / "src"))
from slicecap.fitted_material import charlie_visibility, sheen_albedo  # noqa: E402

THREE = REPOSITORY / "tools" / "consumers" / "node_modules" / "three"

# What each switch changes when it is in `deviations` (three.js's side) rather than not (the
# specification's side).
DEVIATIONS = {
    "visibility": "sheen visibility: V_Neubelt 1 / (4 (n.l + n.v - n.l n.v)), saturated, where "
                  "KHR_materials_sheen's sample implementation takes the Charlie visibility",
    "sheen_albedo": "the albedo scaling's E: IBLSheenBRDF's curve fit exp(a n.v + b), where the "
                    "extension integrates the sheen BRDF itself (D_charlie V_charlie)",
    "diffuse_dimming": "direct diffuse dimmed per channel by (1 - F), where "
                       "KHR_materials_specular dims every channel by 1 - max_value(F)",
    "multiscatter": "direct specular times 1 + F0 (1 / E_ss - 1) (multiScatteringCompensation, "
                    "Turquin), which no glTF text has",
    "fresnel": "Schlick's (1 - v.h)^5 by Epic's exp2 fit",
    "charlie_floor": "D_Charlie's sin^2(h) floored at 2^-7",
}


def _half_floats(words) -> np.ndarray:
    return np.array(words, dtype=np.uint16).view(np.float16).astype(np.float64)


def dfg_lut(three: pathlib.Path = THREE) -> np.ndarray:
    """(16, 16, 2) three.js's DFG table (src/renderers/shaders/DFGLUTData.js: RG16F, u the
    roughness, v n.v), read from the installed file."""
    text = (three / "src" / "renderers" / "shaders" / "DFGLUTData.js").read_text()
    body = text.split("new Uint16Array(", 1)[1].split(")", 1)[0]
    words = [int(w, 16) for w in re.findall(r"0x[0-9a-fA-F]+", body)]
    return _half_floats(words).reshape(16, 16, 2)


def _bilinear(lut: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A LinearFilter, ClampToEdgeWrapping texture read at (u, v) in [0, 1]."""
    size = lut.shape[0]
    x = np.clip(u * size - 0.5, 0, size - 1)
    y = np.clip(v * size - 0.5, 0, size - 1)
    x0, y0 = np.minimum(x.astype(int), size - 2), np.minimum(y.astype(int), size - 2)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    return ((lut[y0, x0] * (1 - fx) + lut[y0, x0 + 1] * fx) * (1 - fy)
            + (lut[y0 + 1, x0] * (1 - fx) + lut[y0 + 1, x0 + 1] * fx) * fy)


def _schlick_weight(v_h: np.ndarray, epic: bool) -> np.ndarray:
    # common.glsl.js F_Schlick: exp2((-5.55473 v.h - 6.98316) v.h) for (1 - v.h)^5.
    return np.exp2((-5.55473 * v_h - 6.98316) * v_h) if epic else (1 - v_h) ** 5


def ibl_sheen_brdf(n_v: np.ndarray, roughness: float) -> np.ndarray:
    """lights_physical_pars_fragment.glsl.js IBLSheenBRDF: the curve fit to the sheen's albedo."""
    r2, r_inv = roughness * roughness, 1.0 / (roughness + 0.1)
    a = -1.9362 + 1.0678 * roughness + 0.4573 * r2 - 0.8469 * r_inv
    b = -0.6014 + 0.5538 * roughness - 0.4670 * r2 - 0.1255 * r_inv
    return np.clip(np.exp(a * n_v + b), 0, 1)


def material_of(gltf_material: dict) -> dict:
    """MeshPhysicalMaterial's uniforms as GLTFLoader and lights_physical_fragment set them."""
    pbr = gltf_material.get("pbrMetallicRoughness", {})
    ext = gltf_material.get("extensions", {})
    spec = ext.get("KHR_materials_specular", {})
    aniso = ext.get("KHR_materials_anisotropy", {})
    sheen = ext.get("KHR_materials_sheen")
    ior = ext.get("KHR_materials_ior", {}).get("ior", 1.5)
    metalness = pbr.get("metallicFactor", 1.0)
    base = np.array(pbr.get("baseColorFactor", [1, 1, 1, 1])[:3], float)
    intensity = spec.get("specularFactor", 1.0)
    specular_color = np.minimum(((ior - 1) / (ior + 1)) ** 2
                                * np.array(spec.get("specularColorFactor", [1, 1, 1]), float),
                                1.0) * intensity
    return {
        "diffuse": base * (1 - metalness),
        "metalness": metalness,
        "roughness": min(max(pbr.get("roughnessFactor", 1.0), 0.045), 1.0),
        "anisotropy": min(aniso.get("anisotropyStrength", 0.0), 1.0),
        "rotation": aniso.get("anisotropyRotation", 0.0),
        "specular_color": specular_color,
        "specular_blended": specular_color * (1 - metalness) + base * metalness,
        "f90": intensity * (1 - metalness) + metalness,
        "sheen_color": np.array(sheen.get("sheenColorFactor", [0, 0, 0]), float) if sheen
        else None,
        "sheen_roughness": min(max(sheen.get("sheenRoughnessFactor", 0.0), 1e-4), 1.0) if sheen
        else 0.0,
    }


def threejs_brdf(gltf_material: dict, deviations=tuple(DEVIATIONS), three=THREE):
    """f(to_light, to_view) -> RGB (1/sr) for (N, 3) unit vectors in the frame TANGENT = x,
    bitangent = y, normal = z: the radiance three.js adds for a point light divided by its
    irradiance n.l E. `deviations`: the names of DEVIATIONS drawn three.js's way."""
    unknown = set(deviations) - set(DEVIATIONS)
    if unknown:
        raise ValueError(f"unknown deviations: {sorted(unknown)}")
    m = material_of(gltf_material)
    lut = dfg_lut(three) if "multiscatter" in deviations else None
    rot = m["rotation"]
    t = np.array([np.cos(rot), np.sin(rot), 0.0])
    b = np.array([-np.sin(rot), np.cos(rot), 0.0])
    alpha = m["roughness"] ** 2
    alpha_t = max(alpha + (1 - alpha) * m["anisotropy"] ** 2, alpha)

    def brdf(light: np.ndarray, view: np.ndarray) -> np.ndarray:
        h = light + view
        h = h / np.linalg.norm(h, axis=-1, keepdims=True)
        n_l, n_v = np.clip(light[:, 2], 0, 1), np.clip(view[:, 2], 0, 1)
        v_h = np.clip(np.sum(view * h, -1), 0, 1)
        w = _schlick_weight(v_h, "fresnel" in deviations)[:, None]
        # BRDF_GGX with USE_ANISOTROPY: D_GGX_Anisotropic, V_GGX_SmithCorrelated_Anisotropic.
        a2 = alpha_t * alpha
        f = np.stack([alpha * (h @ t), alpha_t * (h @ b), a2 * h[:, 2]], -1)
        d = a2 * (a2 / np.sum(f * f, -1)) ** 2 / np.pi

        def length(x):
            return np.linalg.norm(np.stack([alpha_t * (x @ t), alpha * (x @ b), x[:, 2]], -1),
                                  axis=-1)

        vis = 0.5 / np.maximum(n_l * length(view) + n_v * length(light), 1e-6)
        specular = (m["specular_blended"] * (1 - w) + m["f90"] * w) * (vis * d)[:, None]
        if lut is not None:
            # lights_fragment_begin.glsl.js: multiScatteringCompensation.
            dfg = _bilinear(lut, np.full_like(n_v, m["roughness"]), n_v)
            e_ss = (dfg[:, 0] + dfg[:, 1])[:, None]
            specular = specular * (1 + m["specular_blended"] * (1 / e_ss - 1))
        fresnel = m["specular_color"] * (1 - w) + m["f90"] * w
        dimming = (1 - fresnel) if "diffuse_dimming" in deviations else \
            (1 - fresnel.max(-1, keepdims=True))
        value = specular + m["diffuse"] / np.pi * dimming
        if m["sheen_color"] is not None and m["sheen_color"].max() > 0:
            r = m["sheen_roughness"]
            alpha_g = r * r
            sin2h = np.maximum(1 - h[:, 2] ** 2, 0.0078125 if "charlie_floor" in deviations
                               else 0.0)
            d_sheen = (2 + 1 / alpha_g) * sin2h ** (0.5 / alpha_g) / (2 * np.pi)
            if "visibility" in deviations:
                v_sheen = np.clip(1 / (4 * (n_l + n_v - n_l * n_v)), 0, 1)
            else:
                v_sheen = charlie_visibility(n_l, n_v, alpha_g)
            if "sheen_albedo" in deviations:
                e_max = np.maximum(ibl_sheen_brdf(n_v, r), ibl_sheen_brdf(n_l, r))
            else:
                e_max = np.maximum(sheen_albedo(n_v, alpha_g), sheen_albedo(n_l, alpha_g))
            scaling = (1 - m["sheen_color"].max() * e_max)[:, None]
            value = m["sheen_color"] * (d_sheen * v_sheen)[:, None] + value * scaling
        return value

    return brdf
