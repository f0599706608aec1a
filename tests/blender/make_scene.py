# Builds the exporter test's scene in Blender and saves it (run by test_blender.py):
#   blender -b --factory-startup --python make_scene.py -- OUT.blend CHECKER.png
# Five boxes (two of them linked duplicates of one mesh) on a floor, with a Principled,
# a Diffuse with an image texture, a Glossy and a Toon BSDF (which the exporter cannot
# map, so it must warn), a sun, an area light above the camera's view, a world colour.
# tests/blender/handwritten.xml states the same scene in nori's format by hand.
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scene_tools import add_camera  # noqa: E402


blend_file, checker_file = sys.argv[sys.argv.index("--") + 1:][:2]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

# The unit box of tests/blender/box.obj: corners, then per face four corners with uv.
CORNERS = [(x, y, z) for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)]
FACES = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
FACE_UV = [(0, 0), (1, 0), (1, 1), (0, 1)]


def box_mesh(name):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(CORNERS, [], FACES)
    uv = mesh.uv_layers.new(name="UVMap")
    for polygon in mesh.polygons:
        for k, loop in enumerate(polygon.loop_indices):
            uv.data[loop].uv = FACE_UV[k]
    mesh.update()
    return mesh


def add_object(name, mesh, location, scale=1.0, yaw_degrees=0.0):
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    obj.scale = (scale, scale, scale)
    obj.rotation_euler = (0, 0, math.radians(yaw_degrees))
    scene.collection.objects.link(obj)
    return obj


def material(name, node_type, **inputs):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    shader = tree.nodes.new(node_type)
    for key, value in inputs.items():
        shader.inputs[key.replace("_", " ")].default_value = value
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(shader.outputs[0], output.inputs["Surface"])
    return mat, shader


# A 64x64 checker of 8x8 cells, dark blue and light yellow.
image = bpy.data.images.new("checker", 64, 64)
pixels = []
for y in range(64):
    for x in range(64):
        light = ((x // 8) + (y // 8)) % 2 == 0
        pixels += [0.9, 0.8, 0.3, 1.0] if light else [0.1, 0.15, 0.5, 1.0]
image.pixels = pixels
image.filepath_raw = checker_file
image.file_format = "PNG"
image.save()

floor = bpy.data.meshes.new("Floor")
floor.from_pydata([(-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0)], [], [(0, 1, 2, 3)])
floor.uv_layers.new(name="UVMap")
floor.update()
floor.materials.append(material("Grey", "ShaderNodeBsdfDiffuse", Color=(0.6, 0.6, 0.6, 1))[0])
add_object("Floor", floor, (0, 0, 0))

red_box = box_mesh("RedBox")
red_box.materials.append(material("Red", "ShaderNodeBsdfPrincipled",
                                  Base_Color=(0.8, 0.1, 0.1, 1), Roughness=0.4)[0])
add_object("Red", red_box, (-1.5, 0.3, 0.5))
add_object("RedCopy", red_box, (1.4, 1.2, 0.75), scale=1.5, yaw_degrees=30)  # linked duplicate

checker_box = box_mesh("CheckerBox")
checker_material, diffuse = material("Checker", "ShaderNodeBsdfDiffuse")
texture = checker_material.node_tree.nodes.new("ShaderNodeTexImage")
texture.image = bpy.data.images.load(checker_file)
# Closest, not Cycles' default Linear: Cycles interpolates 8-bit sRGB textures before
# decoding them to linear, which darkens the checker's cell edges (about 8% of this
# box's mean); nori decodes first. Point sampling compares the two without that.
texture.interpolation = "Closest"
checker_material.node_tree.links.new(texture.outputs["Color"], diffuse.inputs["Color"])
checker_box.materials.append(checker_material)
add_object("Checker", checker_box, (0.2, -1.4, 0.5), yaw_degrees=-20)

metal_box = box_mesh("MetalBox")
metal_material, glossy = material("Gold", "ShaderNodeBsdfGlossy", Color=(0.9, 0.7, 0.3, 1),
                                  Roughness=0.3)
glossy.distribution = "GGX"
metal_box.materials.append(metal_material)
add_object("Metal", metal_box, (-1.2, 2.2, 0.5))

toon_box = box_mesh("ToonBox")
toon_box.materials.append(material("Toon", "ShaderNodeBsdfToon")[0])
add_object("Toon", toon_box, (2.4, -1.6, 0.4), scale=0.8)

sun = bpy.data.lights.new("Sun", "SUN")
sun.energy = 2.0
sun.angle = 0.0
sun_object = bpy.data.objects.new("Sun", sun)
sun_object.rotation_euler = (math.radians(40), 0, math.radians(30))
scene.collection.objects.link(sun_object)

area = bpy.data.lights.new("Panel", "AREA")
area.energy = 200.0
area.size = 1.0
area_object = bpy.data.objects.new("Panel", area)
area_object.location = (0, 0, 6)
scene.collection.objects.link(area_object)

world = bpy.data.worlds.new("Sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.05, 0.07, 0.1, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
scene.world = world

add_camera(scene, 35, (0, -7, 5), (0, 0, 0.5), 160, 120)

bpy.ops.wm.save_as_mainfile(filepath=blend_file)
print("saved", blend_file)
