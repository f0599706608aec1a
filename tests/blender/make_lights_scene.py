# The exporter test's second scene (run by test_blender.py):
#   blender -b --factory-startup --python make_lights_scene.py -- OUT.blend SKY.png
# What the first scene leaves out: an environment texture seen directly by the camera
# (its orientation), a point light and a spot light on a floor, a box with an Emission
# shader, a glass box, and a camera with depth of field.
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scene_tools import add_camera  # noqa: E402


blend_file, sky_file = sys.argv[sys.argv.index("--") + 1:][:2]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

# A 64 x 32 equirectangular sky whose colour says where it points: red rises with u (around
# the horizon), green with v (toward the zenith), blue is constant. Row 0 is the bottom.
sky = bpy.data.images.new("sky", 64, 32)
pixels = []
for y in range(32):
    for x in range(64):
        pixels += [(x + 0.5) / 64, (y + 0.5) / 32, 0.25, 1.0]
sky.pixels = pixels
sky.filepath_raw = sky_file
sky.file_format = "PNG"
sky.save()

world = bpy.data.worlds.new("Sky")
world.use_nodes = True
tree = world.node_tree
environment = tree.nodes.new("ShaderNodeTexEnvironment")
environment.image = bpy.data.images.load(sky_file)
environment.interpolation = "Closest"
tree.links.new(environment.outputs["Color"], tree.nodes["Background"].inputs["Color"])
tree.nodes["Background"].inputs["Strength"].default_value = 0.5
scene.world = world


def add(name, data, location, rotation=(0, 0, 0)):
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    return obj


def shaded(mesh_name, vertices, faces, node_type, **inputs):
    mesh = bpy.data.meshes.new(mesh_name)
    mesh.from_pydata(vertices, [], faces)
    mesh.update()
    material = bpy.data.materials.new(mesh_name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    shader = nodes.new(node_type)
    for key, value in inputs.items():
        shader.inputs[key].default_value = value
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(shader.outputs[0], output.inputs["Surface"])
    mesh.materials.append(material)
    return mesh


BOX = ([(x, y, z) for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)],
       [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)])

add("Floor", shaded("Floor", [(-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0)], [(0, 1, 2, 3)],
                    "ShaderNodeBsdfDiffuse", Color=(0.7, 0.7, 0.7, 1)), (0, 0, 0))
add("Glow", shaded("Glow", *BOX, "ShaderNodeEmission", Color=(1.0, 0.5, 0.2, 1), Strength=2.0),
    (-1.6, 1.0, 0.5))
add("Glass", shaded("Glass", *BOX, "ShaderNodeBsdfGlass", IOR=1.5, Roughness=0.0),
    (1.4, 0.8, 0.5))

point = bpy.data.lights.new("Bulb", "POINT")
point.energy = 300.0
point.shadow_soft_size = 0.0
add("Bulb", point, (-2.5, -1.0, 2.5))
spot = bpy.data.lights.new("Spot", "SPOT")
spot.energy = 600.0
spot.shadow_soft_size = 0.0
spot.spot_size = math.radians(50)
spot.spot_blend = 0.3
add("Spot", spot, (2.5, -1.5, 3.0), (math.radians(20), 0, 0))

camera = add_camera(scene, 24, (0, -7, 2.2), (0, 0, 1.2), 192, 108)
camera.dof.use_dof = True
camera.dof.focus_distance = 7.0
camera.dof.aperture_fstop = 8.0
bpy.ops.wm.save_as_mainfile(filepath=blend_file)
