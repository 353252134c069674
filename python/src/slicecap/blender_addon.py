"""Imports a glTF from `slicecap fit --gltf` into Blender 4.1+ with its anisotropy fixed up.

Blender's bundled glTF importer copies KHR_materials_anisotropy's strength unchanged into the
Principled BSDF's Anisotropic and connects no Tangent, so Cycles renders a shorter highlight around
Blender's default tangent (docs/material-export.md, "Blender"). For each material slicecap wrote
(the asset's generator "slicecap ..." and the material "slicecap-fit"), this connects a UV-map
Tangent node (the exported meshes' u runs along the exported tangent) and sets Roughness and
Anisotropic so that Cycles' Principled lobe has glTF's two alphas (`blender_inputs`).

One file, three uses (docs/guide/desktop.md, "Blender"):
- a script: `blender --python blender_addon.py -- M.glb [MORE.gltf ...]` imports the files;
  run from Blender's Text Editor ("Run Script") without arguments it registers the operator;
- a single-file add-on (Edit > Preferences > Add-ons > Install from Disk): File > Import >
  "Import slicecap glTF";
- a module: the math and the glTF reading need no `bpy` (imported only inside the Blender-side
  functions), so tests and python/checks/blender_render.py use the same code.
"""

import json
import math
import re
import struct
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

bl_info = {
    "name": "Import slicecap glTF",
    "author": "slicecap",
    "version": (1, 0, 0),
    "blender": (4, 1, 0),
    "location": "File > Import > Import slicecap glTF",
    "description": "glTF import with slicecap's anisotropy mapped to Cycles' Principled BSDF",
    "category": "Import-Export",
}

# Cycles' Principled BSDF (its svm_closure code): aspect = sqrt(1 - 0.9 anisotropic) with
# anisotropic in [0, 1], alpha_x = r^2 / aspect along the tangent, alpha_y = r^2 aspect. The
# ratio alpha_x / alpha_y = 1 / (1 - 0.9 anisotropic) therefore reaches at most 10.
CYCLES_ANISOTROPY_SCALE = 0.9
CYCLES_MAX_ALPHA_RATIO = 1.0 / (1.0 - CYCLES_ANISOTROPY_SCALE)
SLICECAP_MATERIAL_NAMES = ("slicecap-fit", "slicecap-svbrdf")


@dataclass(frozen=True)
class BlenderAnisotropy:
    """Principled BSDF inputs for two GGX alphas, and what Cycles makes of them."""

    roughness: float
    anisotropic: float
    alpha_tangent_wanted: float
    alpha_bitangent_wanted: float
    alpha_tangent: float  # what Cycles renders with these inputs
    alpha_bitangent: float
    clamped: bool  # the wanted ratio exceeds CYCLES_MAX_ALPHA_RATIO: the alphas above differ

    def loss(self) -> str | None:
        """A sentence saying what the clamp changed, or None when nothing was lost."""
        if not self.clamped:
            return None
        ratio = (math.inf if self.alpha_bitangent_wanted == 0.0
                 else self.alpha_tangent_wanted / self.alpha_bitangent_wanted)
        return (f"alpha ratio {ratio:.3g} exceeds Cycles' Principled maximum "
                f"{CYCLES_MAX_ALPHA_RATIO:g}: alphas (tangent, bitangent) "
                f"({self.alpha_tangent:.4g}, {self.alpha_bitangent:.4g}) rendered for "
                f"({self.alpha_tangent_wanted:.4g}, {self.alpha_bitangent_wanted:.4g}), "
                "keeping their geometric mean")


def gltf_alphas(roughness_factor: float, anisotropy_strength: float) -> tuple[float, float]:
    """KHR_materials_anisotropy's (alpha_t, alpha_b): alpha_b = roughness^2, alpha_t =
    mix(alpha_b, 1, strength^2). Raises ValueError naming a factor outside [0, 1]."""
    for name, value in (("roughnessFactor", roughness_factor),
                        ("anisotropyStrength", anisotropy_strength)):
        if not 0.0 <= value <= 1.0:
            raise ValueError(f"glTF {name} {value!r} is outside [0, 1]")
    alpha_b = roughness_factor**2
    return alpha_b + (1.0 - alpha_b) * anisotropy_strength**2, alpha_b


def cycles_alphas(roughness: float, anisotropic: float) -> tuple[float, float]:
    """Cycles' Principled (alpha_x along the tangent, alpha_y) for these inputs, clamping
    Anisotropic to [0, 1] as Cycles does."""
    aspect = math.sqrt(1.0 - CYCLES_ANISOTROPY_SCALE * min(1.0, max(0.0, anisotropic)))
    return roughness**2 / aspect, roughness**2 * aspect


def blender_inputs(alpha_tangent: float, alpha_bitangent: float) -> BlenderAnisotropy:
    """Roughness and Anisotropic giving these alphas in Cycles: r^2 = sqrt(alpha_t alpha_b),
    Anisotropic = (1 - alpha_b / alpha_t) / 0.9. A ratio above 10 is clamped to 10 keeping the
    geometric mean, and `clamped` says so. Raises ValueError for alphas outside [0, 1] or
    alpha_t < alpha_b (Cycles stretches along the tangent only; glTF's law never asks that)."""
    if not (0.0 <= alpha_bitangent <= 1.0 and 0.0 <= alpha_tangent <= 1.0):
        raise ValueError(f"alphas ({alpha_tangent!r}, {alpha_bitangent!r}) are outside [0, 1]")
    if alpha_tangent < alpha_bitangent:
        raise ValueError(f"alpha_tangent {alpha_tangent!r} is below alpha_bitangent "
                         f"{alpha_bitangent!r}: Cycles' Anisotropic stretches along the tangent")
    roughness = (alpha_tangent * alpha_bitangent) ** 0.25
    clamped = alpha_tangent > CYCLES_MAX_ALPHA_RATIO * alpha_bitangent
    if alpha_tangent == 0.0:
        anisotropic = 0.0
    elif clamped:
        anisotropic = 1.0
    else:
        anisotropic = (1.0 - alpha_bitangent / alpha_tangent) / CYCLES_ANISOTROPY_SCALE
    reached_t, reached_b = cycles_alphas(roughness, anisotropic)
    return BlenderAnisotropy(roughness, anisotropic, alpha_tangent, alpha_bitangent,
                             reached_t, reached_b, clamped)


@dataclass(frozen=True)
class SlicecapMaterial:
    """A material of a slicecap glTF, with the factors the re-mapping needs."""

    name: str
    roughness_factor: float
    anisotropy_strength: float
    anisotropy_rotation_rad: float
    textured: bool  # an anisotropy or roughness texture: per-texel values, not re-mapped here


def read_gltf_document(path: str | Path) -> dict[str, Any]:
    """The JSON of a .gltf or .glb file. Raises OSError if unreadable, ValueError naming the file
    if it is neither JSON nor a binary glTF with a JSON chunk."""
    data = Path(path).read_bytes()
    try:
        if data[:4] == b"glTF":
            length, kind = struct.unpack_from("<I4s", data, 12)
            if kind != b"JSON":
                raise ValueError("its first chunk is not JSON")
            document = json.loads(data[20:20 + length].decode("utf-8"))
        else:
            document = json.loads(data.decode("utf-8"))
    except (ValueError, struct.error) as error:
        raise ValueError(f"{path}: not a glTF 2.0 file ({error})") from error
    if not isinstance(document, dict):
        raise ValueError(f"{path}: not a glTF 2.0 file (its JSON is not an object)")
    return document


def slicecap_materials(document: dict[str, Any]) -> list[SlicecapMaterial]:
    """The materials slicecap wrote: none unless the asset's generator starts with "slicecap"."""
    if not str(document.get("asset", {}).get("generator", "")).startswith("slicecap"):
        return []
    found = []
    for material in document.get("materials", []):
        if material.get("name") not in SLICECAP_MATERIAL_NAMES:
            continue
        pbr = material.get("pbrMetallicRoughness", {})
        anisotropy = material.get("extensions", {}).get("KHR_materials_anisotropy", {})
        found.append(SlicecapMaterial(
            material["name"], float(pbr.get("roughnessFactor", 1.0)),
            float(anisotropy.get("anisotropyStrength", 0.0)),
            float(anisotropy.get("anisotropyRotation", 0.0)),
            "anisotropyTexture" in anisotropy or "metallicRoughnessTexture" in pbr))
    return found


def base_name(blender_name: str) -> str:
    """A Blender datablock name without the ".001" Blender appends to keep names unique."""
    return re.sub(r"\.\d{3,}$", "", blender_name)


# ---- Blender-side functions: bpy is imported inside, so the module imports without it. ----

def principled_of(material: Any) -> tuple[Any, Any]:
    """(node tree, Principled BSDF node). Raises RuntimeError naming the material without one."""
    if material.node_tree is not None:
        for node in material.node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                return material.node_tree, node
    raise RuntimeError(f"material {material.name}: no Principled BSDF")


def connect_uv_tangent(tree: Any, principled: Any, uv_map: str) -> bool:
    """Connects a UV-map Tangent node to the Principled BSDF's Tangent unless one is connected:
    without an anisotropy texture the importer connects none and Blender's default tangent is not
    the exported one. Returns whether a node was added."""
    if principled.inputs["Tangent"].is_linked:
        return False
    tangent = tree.nodes.new("ShaderNodeTangent")
    tangent.direction_type = "UV_MAP"
    tangent.uv_map = uv_map
    tangent.location = (principled.location.x - 250, principled.location.y - 400)
    tree.links.new(principled.inputs["Tangent"], tangent.outputs["Tangent"])
    return True


def first_uv_map(material: Any) -> str | None:
    """The first UV map of a mesh using this material, or None if no such mesh has one."""
    import bpy

    for mesh in bpy.data.meshes:
        if any(m == material for m in mesh.materials) and len(mesh.uv_layers) > 0:
            return str(mesh.uv_layers[0].name)
    return None


def apply_to_material(material: Any, source: SlicecapMaterial) -> tuple[BlenderAnisotropy, str]:
    """Connects the tangent and re-maps Roughness, Anisotropic and Anisotropic Rotation of one
    imported material; returns the inputs set and a line for the user (saying any clamp).
    Raises RuntimeError naming the material if it has no Principled BSDF or no UV map."""
    tree, principled = principled_of(material)
    uv_map = first_uv_map(material)
    if uv_map is None:
        raise RuntimeError(f"material {material.name}: no mesh with a UV map uses it, so there is "
                           "no tangent to orient the anisotropy")
    connect_uv_tangent(tree, principled, uv_map)
    inputs = blender_inputs(*gltf_alphas(source.roughness_factor, source.anisotropy_strength))
    principled.inputs["Roughness"].default_value = inputs.roughness
    principled.inputs["Anisotropic"].default_value = inputs.anisotropic
    principled.inputs["Anisotropic Rotation"].default_value = (
        source.anisotropy_rotation_rad / (2.0 * math.pi)) % 1.0
    line = (f"{material.name}: Roughness {inputs.roughness:.4f}, Anisotropic "
            f"{inputs.anisotropic:.4f} (glTF alphas {inputs.alpha_tangent_wanted:.4g}, "
            f"{inputs.alpha_bitangent_wanted:.4g}), tangent from UV map {uv_map}")
    loss = inputs.loss()
    return inputs, line + ("" if loss is None else f"; LOSS: {loss}")


def import_slicecap_gltf(filepath: str) -> list[str]:
    """Imports the file with Blender's glTF importer and fixes up each slicecap material it
    created. Returns one line per material for the user. Raises OSError/ValueError naming an
    unreadable file, RuntimeError if the importer fails or finds no slicecap material."""
    import bpy

    sources = {m.name: m for m in slicecap_materials(read_gltf_document(filepath))}
    if not sources:
        raise RuntimeError(f"{filepath}: no material written by slicecap fit (the asset's "
                           f"generator and a material named one of {SLICECAP_MATERIAL_NAMES})")
    before = set(bpy.data.materials)
    if "FINISHED" not in bpy.ops.import_scene.gltf(filepath=str(filepath)):
        raise RuntimeError(f"{filepath}: Blender's glTF importer failed")
    lines = []
    for material in [m for m in bpy.data.materials if m not in before]:
        source = sources.get(base_name(material.name))
        if source is None:
            continue
        if source.textured:
            lines.append(f"{material.name}: textured (per-texel anisotropy), left as imported")
            continue
        lines.append(apply_to_material(material, source)[1])
    return lines


_registered: list[Any] = []


def _slicecap_menu_entry(menu: Any, _context: Any) -> None:
    menu.layout.operator("import_scene.slicecap_gltf", text="Import slicecap glTF (.glb/.gltf)")


def register() -> None:
    """Registers the operator and its File > Import menu entry (Blender calls this)."""
    import bpy
    from bpy_extras.io_utils import ImportHelper

    class ImportSlicecapGltf(bpy.types.Operator, ImportHelper):
        """Import a glTF from slicecap fit with its anisotropy mapped to Cycles"""

        bl_idname = "import_scene.slicecap_gltf"
        bl_label = "Import slicecap glTF"
        bl_options = {"REGISTER", "UNDO"}
        filename_ext = ".glb"
        # Blender reads properties from annotations that are calls, which mypy refuses.
        filter_glob: bpy.props.StringProperty(  # type: ignore[valid-type]
            default="*.glb;*.gltf", options={"HIDDEN"})

        def execute(self, _context: Any) -> set[str]:
            try:
                lines = import_slicecap_gltf(self.filepath)
            except (OSError, ValueError, RuntimeError) as error:
                self.report({"ERROR"}, str(error))
                return {"CANCELLED"}
            for line in lines:
                self.report({"WARNING"} if "LOSS" in line else {"INFO"}, line)
            return {"FINISHED"}

    bpy.utils.register_class(ImportSlicecapGltf)
    # Run Script twice executes this file twice: drop the earlier run's menu entry, a different
    # function object with the same name, so the menu shows one.
    menu = bpy.types.TOPBAR_MT_file_import
    for draw in [f for f in menu._dyn_ui_initialize()
                 if getattr(f, "__name__", "") == _slicecap_menu_entry.__name__]:
        menu.remove(draw)
    menu.append(_slicecap_menu_entry)
    _registered.append(ImportSlicecapGltf)


def unregister() -> None:
    """Removes what register added (Blender calls this)."""
    import bpy

    bpy.types.TOPBAR_MT_file_import.remove(_slicecap_menu_entry)
    while _registered:
        bpy.utils.unregister_class(_registered.pop())


def main(argv: list[str]) -> int:
    """`blender --python blender_addon.py -- FILE...` imports the files; without files (the Text
    Editor's Run Script) registers the operator. Returns the exit status."""
    files = argv[argv.index("--") + 1:] if "--" in argv else []
    # Blender's Text Editor runs this with Blender's own argv: no "--", so no files.
    if not files:
        register()
        return 0
    for path in files:
        try:
            for line in import_slicecap_gltf(path):
                print(f"slicecap: {line}")
        except (OSError, ValueError, RuntimeError) as error:
            print(f"slicecap: {error}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    status = main(sys.argv)
    if status != 0:
        sys.exit(status)
