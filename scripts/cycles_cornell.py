# Builds nori's diffuse Cornell box (scenes/cbox/cbox.xml with -D sphere=diffuse) in
# Blender and renders it with Cycles, for scripts/bench_cycles.sh:
#   blender -b --factory-startup --python cycles_cornell.py -- MESH_DIR OUT.exr SAMPLES
#       SEED THREADS SIZE
# Prints "render seconds: T", the time of bpy.ops.render.render (scene sync, BVH build
# and path tracing), which is what nori's "Done in" counts.
#
# Cycles' defaults are kept except where the comparison needs the same estimate as
# nori's path_mis (scripts/cycles_common.py): with Cycles' default 4 diffuse bounces, for
# one, a fifth of the box's indirect light would be missing from its image. The light is
# a quad that emits from its front only, as nori's area light does.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_help import exit_with_help  # noqa: E402

if __name__ == "__main__":
    exit_with_help(__file__)  # outside Blender: the comment above is the help

import bpy  # noqa: E402 (after the help, which needs no Blender)
import cycles_common as box  # noqa: E402

mesh_dir, output, samples, seed, threads, size = sys.argv[sys.argv.index("--") + 1:][:6]
scene = box.empty_scene()


def add_obj(name, material):
    """One of scenes/cbox/meshes/*.obj (positions and polygons only), flat."""
    box.add_obj(scene, os.path.join(mesh_dir, name + ".obj"), name, material)


def add_sphere(name, center, radius, albedo):
    """A smooth UV sphere fine enough that its facets (at most 1e-4 off the sphere) do
    not show at 512 pixels."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=radius,
                                         location=box.to_blender(*center))
    sphere = bpy.context.active_object
    sphere.name = name
    bpy.ops.object.shade_smooth()
    sphere.data.materials.append(box.diffuse_material(name, albedo))


white = (0.73, 0.71, 0.68)
for wall in ("floor", "ceiling", "back"):
    add_obj(wall, box.diffuse_material(wall, white))
add_obj("left", box.diffuse_material("left", (0.63, 0.065, 0.05)))
add_obj("right", box.diffuse_material("right", (0.14, 0.45, 0.091)))
add_sphere("DiffuseSphere", (-0.45, 0.35, -0.35), 0.35, white)
add_sphere("SecondSphere", (0.45, 0.35, 0.3), 0.35, (0.5, 0.5, 0.5))  # nori's default albedo
# nori's light: the quad of light.obj, radiance (17, 12, 4) on its front (facing down).
add_obj("light", box.light_material((17.0, 12.0, 4.0)))
box.black_world(scene)
# nori's camera: at (0, 1, 3.85) looking at (0, 1, 0), 39° field of view, square image.
box.add_camera(scene, (0.0, 1.0, 3.85), 39.0, size)
box.render(scene, output, samples, seed, threads)
