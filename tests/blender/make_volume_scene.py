# The exporter test's third scene (run by test_blender.py):
#   blender -b --factory-startup --python make_volume_scene.py -- OUT.blend
# Volumes on meshes: a box of fog (a Principled Volume with a colour, an absorption
# colour and forward scattering, no surface shader), a box of tinted absorbing glass (a
# Glass surface holding a Volume Absorption) and a box of Volume Scatter, on a grey floor
# under a sun and a blue-grey sky.
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scene_tools import add_camera  # noqa: E402


blend_file = sys.argv[sys.argv.index("--") + 1:][0]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

# The unit box's corners and faces (tests/blender/box.obj).
CORNERS = [(x, y, z) for z in (-0.5, 0.5) for y in (-0.5, 0.5) for x in (-0.5, 0.5)]
FACES = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
# Box name: (centre, edge length), in Blender's z-up frame; test_blender.py reads the same.
# They float above the floor (a face on the floor's plane would leave which of the two a
# ray meets to rounding), each casting a shadow that the camera sees.
BOXES = {"Fog": ((-1.3, 0.0, 1.1), 1.6), "Tinted": ((1.2, 0.6, 0.9), 1.2),
         "Haze": ((0.3, 2.4, 1.0), 1.4)}


def material(name, volume_type, surface_type=None, **inputs):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    output = tree.nodes.new("ShaderNodeOutputMaterial")
    volume = tree.nodes.new(volume_type)
    for key, value in inputs.items():
        volume.inputs[key.replace("_", " ")].default_value = value
    tree.links.new(volume.outputs[0], output.inputs["Volume"])
    if surface_type is not None:
        surface = tree.nodes.new(surface_type)
        tree.links.new(surface.outputs[0], output.inputs["Surface"])
        return mat, surface
    return mat, None


def add_box(name, mat):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(CORNERS, [], FACES)
    mesh.update()
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    centre, size = BOXES[name]
    obj.location = centre
    obj.scale = (size, size, size)
    scene.collection.objects.link(obj)


fog, _ = material("Fog", "ShaderNodeVolumePrincipled", Color=(0.9, 0.7, 0.5, 1), Density=1.2,
                  Anisotropy=0.5, Absorption_Color=(0.3, 0.5, 0.8, 1))
add_box("Fog", fog)
tinted, glass = material("Tinted", "ShaderNodeVolumeAbsorption", "ShaderNodeBsdfGlass",
                         Color=(0.4, 0.7, 0.9, 1), Density=1.5)
glass.inputs["Roughness"].default_value = 0.0
glass.inputs["IOR"].default_value = 1.33
glass.distribution = "SHARP"
add_box("Tinted", tinted)
haze, _ = material("Haze", "ShaderNodeVolumeScatter", Color=(0.6, 0.8, 0.9, 1), Density=0.8,
                   Anisotropy=-0.3)
add_box("Haze", haze)

floor = bpy.data.meshes.new("Floor")
floor.from_pydata([(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)], [], [(0, 1, 2, 3)])
floor.update()
grey = bpy.data.materials.new("Grey")
grey.use_nodes = True
grey.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.5, 0.5, 0.5, 1)
grey.node_tree.nodes.remove(grey.node_tree.nodes["Principled BSDF"])
diffuse = grey.node_tree.nodes.new("ShaderNodeBsdfDiffuse")
diffuse.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
grey.node_tree.links.new(diffuse.outputs[0],
                         grey.node_tree.nodes["Material Output"].inputs["Surface"])
floor.materials.append(grey)
floor_object = bpy.data.objects.new("Floor", floor)
scene.collection.objects.link(floor_object)

sun = bpy.data.lights.new("Sun", "SUN")
sun.energy = 3.0
sun.angle = 0.0
sun_object = bpy.data.objects.new("Sun", sun)
sun_object.rotation_euler = (math.radians(35), 0, math.radians(-40))
scene.collection.objects.link(sun_object)

world = bpy.data.worlds.new("Sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.2, 0.25, 0.35, 1)
scene.world = world

add_camera(scene, 30, (0.5, -7.0, 3.5), (0, 0.6, 0.6), 160, 120)

bpy.ops.wm.save_as_mainfile(filepath=blend_file)
print("saved", blend_file)
