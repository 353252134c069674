"""The one scene every consumer render of scripts/consumer-check uses (Mitsuba, three.js, Blender):
the exported glTF's own preview sphere, one point light, one camera, no environment; and how
the renders are compared (mean CIE76 dE of 8-bit sRGB over the lit pixels).

The sphere comes from the glTF file itself (its POSITION, NORMAL and TANGENT), so every renderer
shades the same triangles with the same tangent frame (docs/material-export.md, "The frame").
Coordinates are glTF's: metres, y up, right-handed.
"""

import base64
import dataclasses
import json
import os

import numpy as np

from slicecap.image_metrics import delta_e_8bit, to_8bit

SIZE_PX = 128
FOV_DEG = 30.0
CAMERA_DISTANCE_M = 2.2
CAMERA_PITCH_DEG = 15.0
# The light: azimuth counter-clockwise from the camera's direction seen from above, elevation
# above the sphere's equator, distance from its centre; intensity in W/sr (three.js candela and
# Mitsuba's point "intensity" are the same radiometric quantity here: no tone mapping, linear).
LIGHT_AZIMUTH_DEG = 40.0
LIGHT_ELEVATION_DEG = 30.0
LIGHT_DISTANCE_M = 3.0
LIGHT_INTENSITY_W_SR = 12.0
# A pixel is "lit" when the reference render's 8-bit luminance-ish maximum reaches this: the
# unlit side of the sphere and the background carry no information about the BSDF.
LIT_MIN_8BIT = 8
_COMPONENT = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32,
              5126: np.float32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


@dataclasses.dataclass(frozen=True)
class Sphere:
    """The glTF preview sphere in world coordinates: per-vertex arrays and triangle indices."""
    positions: np.ndarray  # (n, 3)
    normals: np.ndarray  # (n, 3)
    tangents: np.ndarray  # (n, 3), the glTF TANGENT's xyz (w = +1)
    triangles: np.ndarray  # (m, 3)
    centre: np.ndarray  # (3,)
    node_index: int


def _buffer(gltf: dict, index: int) -> bytes:
    uri = gltf["buffers"][index]["uri"]
    prefix = "base64,"
    if not uri.startswith("data:") or prefix not in uri:
        raise ValueError(f"buffer {index} is not an embedded data: URI")
    return base64.b64decode(uri.split(prefix, 1)[1])


def _accessor(gltf: dict, index: int) -> np.ndarray:
    accessor = gltf["accessors"][index]
    view = gltf["bufferViews"][accessor["bufferView"]]
    data = _buffer(gltf, view["buffer"])
    dtype = np.dtype(_COMPONENT[accessor["componentType"]])
    width = _WIDTH[accessor["type"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    stride = view.get("byteStride", dtype.itemsize * width)
    rows = [np.frombuffer(data, dtype, width, start + i * stride)
            for i in range(accessor["count"])]
    return np.array(rows)


def read_sphere(gltf_path) -> Sphere:
    """The node whose mesh is named like a sphere, from a .gltf with an embedded buffer. Raises
    ValueError naming the file when there is none or it lacks NORMAL/TANGENT."""
    with open(gltf_path, encoding="utf-8") as file:
        gltf = json.load(file)
    for node_index, node in enumerate(gltf.get("nodes", [])):
        mesh = gltf["meshes"][node["mesh"]] if "mesh" in node else None
        if mesh is None or "sphere" not in (mesh.get("name", "") + node.get("name", "")).lower():
            continue
        primitive = mesh["primitives"][0]
        attributes = primitive["attributes"]
        missing = [a for a in ("POSITION", "NORMAL", "TANGENT") if a not in attributes]
        if missing:
            raise ValueError(f"{gltf_path}: the sphere has no {', '.join(missing)}")
        if "rotation" in node or "scale" in node or "matrix" in node:
            raise ValueError(f"{gltf_path}: the sphere node is rotated or scaled (not expected)")
        centre = np.array(node.get("translation", [0.0, 0.0, 0.0]), dtype=np.float64)
        tangents = _accessor(gltf, attributes["TANGENT"]).astype(np.float64)
        if np.any(tangents[:, 3] != 1.0):
            raise ValueError(f"{gltf_path}: a sphere tangent has w != +1")
        return Sphere(
            positions=_accessor(gltf, attributes["POSITION"]).astype(np.float64) + centre,
            normals=_accessor(gltf, attributes["NORMAL"]).astype(np.float64),
            tangents=tangents[:, :3],
            triangles=_accessor(gltf, primitive["indices"]).reshape(-1, 3).astype(np.int64),
            centre=centre,
            node_index=node_index,
        )
    raise ValueError(f"{gltf_path}: no node with a sphere mesh")


@dataclasses.dataclass(frozen=True)
class View:
    """Camera and light in world coordinates (glTF's, y up)."""
    camera_position: list
    target: list
    fov_deg: float
    light_position: list
    light_intensity_w_sr: float
    size_px: int


def view_of(sphere: Sphere) -> View:
    c = sphere.centre
    pitch = np.radians(CAMERA_PITCH_DEG)
    camera = c + CAMERA_DISTANCE_M * np.array([0.0, np.sin(pitch), np.cos(pitch)])
    az, el = np.radians(LIGHT_AZIMUTH_DEG), np.radians(LIGHT_ELEVATION_DEG)
    light = c + LIGHT_DISTANCE_M * np.array([np.sin(az) * np.cos(el), np.sin(el),
                                             np.cos(az) * np.cos(el)])
    return View(camera.tolist(), c.tolist(), FOV_DEG, light.tolist(), LIGHT_INTENSITY_W_SR,
                SIZE_PX)


def rotated_tangents(sphere: Sphere, angle_deg: float) -> np.ndarray:
    """The vertex tangents turned by angle_deg about the normal, toward the bitangent
    (n x t, glTF's bitangent for w = +1): counter-clockwise seen from outside."""
    a = np.radians(angle_deg)
    t = sphere.tangents - sphere.normals * np.sum(sphere.normals * sphere.tangents, 1)[:, None]
    t /= np.linalg.norm(t, axis=1)[:, None]
    b = np.cross(sphere.normals, t)
    return np.cos(a) * t + np.sin(a) * b


def unshared_mesh_with_tangent_uvs(sphere: Sphere, angle_deg: float):
    """Positions, normals, UVs and faces of the sphere with every triangle's three vertices of its
    own, whose UVs are the vertices projected on the triangle's (tangent, bitangent): a renderer
    that derives its tangent from dp/du (Mitsuba) then finds the glTF tangent turned by
    angle_deg, triangle by triangle. Returns (positions, normals, uvs, faces)."""
    tangents = rotated_tangents(sphere, angle_deg)
    p = sphere.positions[sphere.triangles]  # (m, 3, 3)
    face_normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    # The UV sphere's pole rows hold zero-area triangles (two corners at the pole): not drawn.
    drawn = np.linalg.norm(face_normal, axis=1) > 1e-12
    corners, p, face_normal = sphere.triangles[drawn], p[drawn], face_normal[drawn]
    face_normal /= np.linalg.norm(face_normal, axis=1)[:, None]
    t = tangents[corners].mean(axis=1)
    t -= face_normal * np.sum(face_normal * t, 1)[:, None]
    t /= np.linalg.norm(t, axis=1)[:, None]
    b = np.cross(face_normal, t)
    uvs = np.stack([np.einsum("mkj,mj->mk", p, t), np.einsum("mkj,mj->mk", p, b)], axis=-1)
    faces = np.arange(3 * len(corners)).reshape(-1, 3)
    return (p.reshape(-1, 3), sphere.normals[corners].reshape(-1, 3), uvs.reshape(-1, 2), faces)


def write_ply(path, positions, normals, uvs, faces) -> None:
    """A binary little-endian PLY with x y z nx ny nz u v per vertex (Mitsuba's `ply` reads it)."""
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(positions)}\n"
        + "".join(f"property float {n}\n" for n in ("x", "y", "z", "nx", "ny", "nz", "u", "v"))
        + f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    vertices = np.concatenate([positions, normals, uvs], axis=1).astype("<f4")
    face_rows = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", 3)])
    face_rows["n"] = 3
    face_rows["i"] = faces
    with open(path, "wb") as file:
        file.write(header.encode("ascii"))
        file.write(vertices.tobytes())
        file.write(face_rows.tobytes())


def lit_mask(reference8: np.ndarray) -> np.ndarray:
    return reference8.max(axis=-1) >= LIT_MIN_8BIT


def compare_8bit(reference8: np.ndarray, test8: np.ndarray, mask: np.ndarray) -> dict:
    """Mean and 95th-percentile CIE76 dE over `mask`, and the share of masked pixels above 10."""
    delta = delta_e_8bit(reference8[mask], test8[mask])
    return {"delta_e": float(np.mean(delta)), "delta_e_p95": float(np.percentile(delta, 95)),
            "share_above_10": float(np.mean(delta > 10.0)), "lit_pixels": int(mask.sum())}


def encode(linear: np.ndarray, exposure: float) -> np.ndarray:
    return to_8bit(linear, exposure)



def mitsuba_reference(mitsuba_out: str, row: dict, fit_path: str):
    """(8-bit reference, its name) that a glTF render is judged against: Mitsuba's render of the
    exported snippet, except for a fit with a sheen or a clear coat, which the snippet only
    approximates (a GGX stand-in, no Charlie sheen in Mitsuba 3; a blended, undimmed coat, no
    layered one: docs/material-export.md, `sheen-form`, `coat-form`); then the fit tabulated on
    the grid and rendered through the slicecap plugin (the fit's own model, at the grid's
    resolution)."""
    with open(fit_path, encoding="utf-8") as file:
        parameters = json.load(file)["parameters"]
    sheen = parameters.get("sheen_colour", {"value": [0.0]})["value"]
    coat_weight = parameters.get("coat_weight", {"value": 0.0})["value"]
    key = "fit-tabulated" if max(sheen) > 0.01 or coat_weight > 0.01 else "fit"
    name = row["material"]
    linear = np.load(os.path.join(mitsuba_out, f"{name}-mitsuba-{key}.npy"))
    return encode(linear, row["exposure"]), {"fit": "snippet",
                                             "fit-tabulated": "tabulated fit"}[key]


def judge(mitsuba_out: str, row: dict, image8: np.ndarray, tolerance: float) -> dict:
    """A glTF render (8-bit, the mitsuba row's exposure) against mitsuba_reference, and the
    negative control: against Mitsuba's render of the snippet with its tangent turned by 90 deg,
    which must be farther than the reference is (else the comparison could not tell the right
    frame from a wrong one; for weak lobes, as the satins', a turned tangent moves the image less
    than the renderers' differences do, so the tolerance cannot be the bar).
    The control is skipped (None) for a fit with a sheen or a coat, whose reference is not the
    snippet."""
    name = row["material"]
    reference, against = mitsuba_reference(mitsuba_out, row,
                                           os.path.join(mitsuba_out, f"{name}.json"))
    result = {"against": f"Mitsuba's {against}",
              **compare_8bit(reference, image8, lit_mask(reference) | lit_mask(image8))}
    result["control_delta_e"] = None
    if against == "snippet":
        control = encode(np.load(os.path.join(mitsuba_out, f"{name}-mitsuba-control.npy")),
                         row["exposure"])
        result["control_delta_e"] = compare_8bit(
            control, image8, lit_mask(control) | lit_mask(image8))["delta_e"]
    result["ok"] = result["delta_e"] <= tolerance and (
        result["control_delta_e"] is None or result["control_delta_e"] > result["delta_e"])
    return result


def describe(result: dict) -> str:
    control = result["control_delta_e"]
    return (f"vs {result['against']:22s}: mean dE {result['delta_e']:.2f} (p95 "
            f"{result['delta_e_p95']:.2f}); control (tangent + 90 deg) "
            f"{'n/a' if control is None else f'{control:.2f}'}")
