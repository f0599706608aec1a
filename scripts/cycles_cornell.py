# Builds nori's diffuse Cornell box (scenes/cbox/cbox.xml with -D sphere=diffuse) in
# Blender and renders it with Cycles, for scripts/bench_cycles.sh:
#   blender -b --factory-startup --python cycles_cornell.py -- MESH_DIR OUT.exr SAMPLES
#       SEED THREADS SIZE
# Prints "render seconds: T", the time of bpy.ops.render.render (scene sync, BVH build
# and path tracing), which is what nori's "Done in" counts.
#
# Cycles' defaults are kept except where the comparison needs the same estimate as
# nori's path_mis: no denoising, no clamping, no adaptive sampling (SAMPLES samples in
# every pixel), a box filter one pixel wide (nori's box of radius 0.5), and 64 bounces of
# every kind instead of 12 (4 diffuse), since path_mis ends paths by Russian roulette
# alone: with Cycles' default 4 diffuse bounces, a fifth of the box's indirect light would
# be missing from its image. The light is a quad that emits from its front only, as
# nori's area light does.
import math
import os
import sys
import time

if __name__ == "__main__" and sys.argv[1:2] in (["-h"], ["--help"]):
    # Outside Blender: the comment above is the help.
    with open(__file__) as source:
        for line in source:
            if not line.startswith("#"):
                break
            print(line[2:].rstrip())
    sys.exit(0)

import bpy  # noqa: E402 (after the help, which needs no Blender)

mesh_dir, output, samples, seed, threads, size = sys.argv[sys.argv.index("--") + 1:][:6]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


def to_blender(x, y, z):
    """nori's scene is y-up, Blender's z-up: a quarter turn about x."""
    return (x, -z, y)


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


def add_obj(name, albedo=(0.0, 0.0, 0.0), material=None):
    """One of scenes/cbox/meshes/*.obj (positions and polygons only) as a flat mesh, with
    `material` or a diffuse one of `albedo`."""
    vertices, faces = [], []
    with open(os.path.join(mesh_dir, name + ".obj")) as obj:
        for line in obj:
            fields = line.split()
            if fields and fields[0] == "v":
                vertices.append(to_blender(*map(float, fields[1:4])))
            elif fields and fields[0] == "f":
                faces.append([int(f.split("/")[0]) - 1 for f in fields[1:]])
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    mesh.materials.append(material or diffuse_material(name, albedo))
    mesh.update()
    scene.collection.objects.link(bpy.data.objects.new(name, mesh))


def add_sphere(name, center, radius, albedo):
    """A smooth UV sphere fine enough that its facets (at most 1e-4 off the sphere) do
    not show at 512 pixels."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=radius,
                                         location=to_blender(*center))
    sphere = bpy.context.active_object
    sphere.name = name
    bpy.ops.object.shade_smooth()
    sphere.data.materials.append(diffuse_material(name, albedo))


white = (0.73, 0.71, 0.68)
for wall in ("floor", "ceiling", "back"):
    add_obj(wall, white)
add_obj("left", (0.63, 0.065, 0.05))
add_obj("right", (0.14, 0.45, 0.091))
add_sphere("DiffuseSphere", (-0.45, 0.35, -0.35), 0.35, white)
add_sphere("SecondSphere", (0.45, 0.35, 0.3), 0.35, (0.5, 0.5, 0.5))  # nori's default albedo

# nori's light: the quad of light.obj, radiance (17, 12, 4) on its front (facing down)
# and black behind, as nori's one-sided area light with its black diffuse BSDF. (An area
# lamp would be one-sided too, but Cycles 3.4 does not show lamps to the camera.)
light_material = bpy.data.materials.new("Light")
light_material.use_nodes = True
tree = light_material.node_tree
tree.nodes.clear()
emission = tree.nodes.new("ShaderNodeEmission")
emission.inputs["Color"].default_value = (1.0, 12.0 / 17.0, 4.0 / 17.0, 1.0)
emission.inputs["Strength"].default_value = 17.0  # radiance, for an emission shader
black = tree.nodes.new("ShaderNodeBsdfDiffuse")
black.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
geometry = tree.nodes.new("ShaderNodeNewGeometry")
mix = tree.nodes.new("ShaderNodeMixShader")
tree.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
tree.links.new(emission.outputs["Emission"], mix.inputs[1])
tree.links.new(black.outputs["BSDF"], mix.inputs[2])
out = tree.nodes.new("ShaderNodeOutputMaterial")
tree.links.new(mix.outputs["Shader"], out.inputs["Surface"])
add_obj("light", material=light_material)

world = bpy.data.worlds.new("Black")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
scene.world = world

# nori's camera: at (0, 1, 3.85) looking at (0, 1, 0), 39° field of view, square image.
camera = bpy.data.cameras.new("Camera")
camera.angle = math.radians(39.0)
camera.sensor_fit = "AUTO"
camera_object = bpy.data.objects.new("Camera", camera)
camera_object.location = to_blender(0.0, 1.0, 3.85)
camera_object.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # looks along +y, z up
scene.collection.objects.link(camera_object)
scene.camera = camera_object
scene.render.resolution_x = scene.render.resolution_y = int(size)
scene.render.resolution_percentage = 100

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
