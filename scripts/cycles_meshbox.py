# Builds the mesh-sphere box (scenes/meshbox, written by scripts/make_meshbox.py) in
# Blender from the same files and renders it with Cycles, for scripts/bench_cycles.sh:
#   blender -b --factory-startup --python cycles_meshbox.py -- SCENE_DIR OUT.exr SAMPLES
#       SEED THREADS SIZE
# Prints "render seconds: T" (see scripts/cycles_common.py for the settings: those of
# nori's path_mis). The spheres shade with the OBJ's vertex normals, as nori's do.
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_help import exit_with_help  # noqa: E402

if __name__ == "__main__":
    exit_with_help(__file__)  # outside Blender: the comment above is the help

import cycles_common as box  # noqa: E402 (after the help, which needs no Blender)
from make_meshbox import RADIANCE, SPHERES, WALLS  # noqa: E402

scene_dir, output, samples, seed, threads, size = sys.argv[sys.argv.index("--") + 1:][:6]
scene = box.empty_scene()
meshes = os.path.join(scene_dir, "meshes")
for name, albedo in WALLS.items():
    box.add_obj(scene, os.path.join(meshes, name + ".obj"), name,
                box.diffuse_material(name, albedo))
for name, center, radius, albedo in SPHERES:
    box.add_obj(scene, os.path.join(meshes, "sphere.obj"), name,
                box.diffuse_material(name, albedo), scale=radius, offset=center)
box.add_obj(scene, os.path.join(meshes, "light.obj"), "light",
            box.light_material(RADIANCE))
box.black_world(scene)
box.add_camera(scene, (0.0, 0.0, 3.6), 40.0, size)
box.render(scene, output, samples, seed, threads)
