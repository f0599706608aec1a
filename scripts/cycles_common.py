# What scripts/cycles_cornell.py and scripts/cycles_meshbox.py share: building one of
# nori's boxes in Blender (y-up OBJ meshes, Lambertian materials, a one-sided emitting
# quad, a pinhole camera) and rendering it with Cycles as nori's path_mis renders: no
# denoising, no clamping, no adaptive sampling (SAMPLES samples in every pixel), a box
# filter one pixel wide (nori's box of radius 0.5), and 64 bounces of every kind instead
# of 12 (4 diffuse), since path_mis ends paths by Russian roulette alone.
import math
import sys
import time

if __name__ == "__main__":
    # A module for the two scripts; run alone (outside Blender), it prints the comment above.
    from script_help import exit_with_help

    exit_with_help(__file__, always=True)

import bpy  # noqa: E402 (after the help, which needs no Blender)


def to_blender(x, y, z):
    """nori's scenes are y-up, Blender's z-up: a quarter turn about x."""
    return (x, -z, y)


def empty_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def diffuse_material(name, albedo):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    shader = tree.nodes.new("ShaderNodeBsdfDiffuse")
    shader.inputs["Color"].default_value = (*albedo, 1.0)
    shader.inputs["Roughness"].default_value = 0.0  # Lambert, as nori's diffuse
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(shader.outputs[0], out.inputs["Surface"])
    return material


def light_material(radiance):
    """Emits `radiance` from the front and is black behind, as nori's one-sided area light
    with its black diffuse BSDF. (An area lamp would be one-sided too, but Cycles 3.4
    does not show lamps to the camera.)"""
    material = bpy.data.materials.new("Light")
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    emission = tree.nodes.new("ShaderNodeEmission")
    strength = max(radiance)
    emission.inputs["Color"].default_value = (*(c / strength for c in radiance), 1.0)
    emission.inputs["Strength"].default_value = strength  # radiance, for an emission shader
    black = tree.nodes.new("ShaderNodeBsdfDiffuse")
    black.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    mix = tree.nodes.new("ShaderNodeMixShader")
    tree.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
    tree.links.new(emission.outputs["Emission"], mix.inputs[1])
    tree.links.new(black.outputs["BSDF"], mix.inputs[2])
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return material


def add_obj(scene, path, name, material, scale=1.0, offset=(0.0, 0.0, 0.0)):
    """An OBJ file (v, vn and f records) as a mesh, its positions scaled by `scale` and
    moved by `offset` (nori's toWorld of scale then translate). With vn records the faces
    shade smoothly with exactly those normals, as nori's vertex normals; without, flat."""
    vertices, normals, faces, face_normals = [], [], [], []
    with open(path) as obj:
        for line in obj:
            fields = line.split()
            if fields and fields[0] == "v":
                position = [scale * float(x) + o for x, o in zip(fields[1:4], offset)]
                vertices.append(to_blender(*position))
            elif fields and fields[0] == "vn":
                normals.append(to_blender(*map(float, fields[1:4])))
            elif fields and fields[0] == "f":
                corners = [f.split("/") for f in fields[1:]]
                faces.append([int(c[0]) - 1 for c in corners])
                if normals:
                    face_normals.append([int(c[2]) - 1 for c in corners])
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.materials.append(material)
    if normals:
        mesh.use_auto_smooth = True
        for polygon in mesh.polygons:
            polygon.use_smooth = True
        mesh.normals_split_custom_set(
            [normals[i] for corners in face_normals for i in corners])
    mesh.update()
    scene.collection.objects.link(bpy.data.objects.new(name, mesh))


def black_world(scene):
    world = bpy.data.worlds.new("Black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world


def add_camera(scene, origin, fov_degrees, size):
    """A pinhole at `origin` looking along nori's −z, `fov_degrees` wide, square image."""
    camera = bpy.data.cameras.new("Camera")
    camera.angle = math.radians(fov_degrees)
    camera.sensor_fit = "AUTO"
    camera_object = bpy.data.objects.new("Camera", camera)
    camera_object.location = to_blender(*origin)
    camera_object.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # looks along +y, z up
    scene.collection.objects.link(camera_object)
    scene.camera = camera_object
    scene.render.resolution_x = scene.render.resolution_y = int(size)
    scene.render.resolution_percentage = 100


def render(scene, output, samples, seed, threads):
    """Renders with the settings above, writes OUTPUT (32-bit EXR) and prints "render
    seconds: T", the time of bpy.ops.render.render (scene sync, BVH build and path
    tracing), which is what nori's "Done in" counts."""
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = int(samples)
    cycles.seed = int(seed)
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                    "transparent_max_bounces", "volume_bounces"):
        setattr(cycles, bounces, 64)
    scene.render.threads_mode = "FIXED"
    scene.render.threads = int(threads)
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = output
    start = time.perf_counter()
    bpy.ops.render.render()
    seconds = time.perf_counter() - start
    bpy.data.images["Render Result"].save_render(output)
    print(f"sampling pattern: {cycles.sampling_pattern}")
    print(f"render seconds: {seconds:.3f}")
