"""Runs inside PyPI `bpy` (Blender as a Python module, in a venv of its own that
scripts/consumer-check makes): imports an exported glTF with Blender's bundled glTF importer, reads
the anisotropy the importer put on the Principled BSDF, and renders the glTF's sphere with Cycles
(CPU) in the scene of consumer_scene.py, written by python/checks/blender_gltf.py as VIEW.json
(glTF coordinates). Writes OUT.npy (linear RGB, rows top first) and OUT.json (the Principled
inputs, the Blender version).

Without `addon`, the glTF is imported as Blender's importer leaves it, plus a UV-map Tangent node;
with `addon`, through slicecap's Blender add-on (python/src/slicecap/blender_addon.py, loaded from
its file as Blender loads a single-file add-on): the same tangent and Roughness and Anisotropic
re-mapped to glTF's two alphas.

Usage: python blender_render.py MODEL.gltf VIEW.json OUT [SAMPLES [addon]]
"""

import importlib.util
import json
import math
import os
import sys

import bpy
import numpy as np
from mathutils import Vector

ADDON_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src", "slicecap",
                          "blender_addon.py")
_spec = importlib.util.spec_from_file_location("slicecap_blender_addon", ADDON_FILE)
addon = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(addon)

INPUTS = ("Base Color", "Roughness", "Anisotropic", "Anisotropic Rotation", "IOR",
          "Specular IOR Level", "Specular Tint", "Sheen Weight", "Sheen Tint", "Sheen Roughness",
          "Coat Weight", "Coat Roughness", "Coat IOR", "Coat Tint")


def to_blender(p) -> Vector:
    """glTF's y-up point in Blender's z-up frame, as the importer converts (x, -z, y)."""
    return Vector((p[0], -p[2], p[1]))


def value(socket):
    v = socket.default_value
    return [float(x) for x in v] if hasattr(v, "__len__") else float(v)


def import_sphere(gltf_path, through_addon):
    """The glTF's sphere, imported by Blender's importer or through the add-on (whose lines,
    one per material, are returned beside it); the other meshes are hidden from the render."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if through_addon:
        lines = addon.import_slicecap_gltf(gltf_path)
    else:
        bpy.ops.import_scene.gltf(filepath=gltf_path)
        lines = []
    spheres = [o for o in bpy.context.scene.objects
               if o.type == "MESH" and "sphere" in (o.name + o.data.name).lower()]
    if len(spheres) != 1:
        raise RuntimeError(f"{gltf_path}: expected one sphere mesh, found {len(spheres)}")
    for obj in bpy.context.scene.objects:
        if obj.type == "MESH" and obj is not spheres[0]:
            obj.hide_render = True
    return spheres[0], lines


def scene_from(view, samples):
    scene = bpy.context.scene
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.data.sensor_fit = "HORIZONTAL"
    camera.data.angle = math.radians(view["fov_deg"])
    camera.location = to_blender(view["camera_position"])
    direction = to_blender(view["target"]) - camera.location
    camera.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(camera)
    scene.camera = camera
    light = bpy.data.lights.new("key", "POINT")
    # The glTF importer's own conversion (KHR_lights_punctual, "COMPAT" units): W = 4 pi W/sr.
    light.energy = 4.0 * math.pi * view["light_intensity_w_sr"]
    light.shadow_soft_size = 0.0
    if hasattr(light, "use_soft_falloff"):
        light.use_soft_falloff = False
    light_object = bpy.data.objects.new("key", light)
    light_object.location = to_blender(view["light_position"])
    scene.collection.objects.link(light_object)
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.pixel_filter_type = "BOX"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = 1
    scene.render.resolution_x = scene.render.resolution_y = view["size_px"]
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"


def main(argv):
    gltf_path, view_path, out = argv[:3]
    samples = int(argv[3]) if len(argv) > 3 else 16
    through_addon = len(argv) > 4 and argv[4] == "addon"
    with open(view_path, encoding="utf-8") as file:
        view = json.load(file)
    sphere, addon_lines = import_sphere(gltf_path, through_addon)
    tree, principled = addon.principled_of(sphere.active_material)
    imported = {name: value(principled.inputs[name]) for name in INPUTS
                if name in principled.inputs}
    imported["tangent_linked"] = principled.inputs["Tangent"].is_linked
    imported["distribution"] = principled.distribution
    if not through_addon:
        # As the desktop guide's manual step: the importer connects no tangent.
        addon.connect_uv_tangent(tree, principled, sphere.data.uv_layers[0].name)
    scene_from(view, samples)
    bpy.context.scene.render.filepath = out + ".exr"
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(out + ".exr")
    pixels = np.array(image.pixels[:], dtype=np.float64).reshape(
        image.size[1], image.size[0], image.channels)
    np.save(out + ".npy", pixels[::-1, :, :3])
    with open(out + ".json", "w", encoding="utf-8") as file:
        json.dump({"blender": bpy.app.version_string, "principled": imported,
                   "addon": addon_lines if through_addon else None}, file, indent=1)


if __name__ == "__main__":
    main(sys.argv[1:])
    # bpy 4.2 as a module segfaults in its interpreter teardown (measured here, after every
    # output was written and closed); leave without the teardown so the exit code means success.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
