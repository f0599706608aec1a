# Renders the open .blend file with Cycles at settings matching nori's path_mis, to a
# linear 32-bit EXR (run by test_blender.py):
#   blender -b scene.blend --python render_cycles.py -- OUT.exr SAMPLES [SEED]
# No denoising, no clamping, no light tree or filter glossy tricks, 64 bounces of every
# kind, volumes included (nori's path_mis and volpath are unbounded with Russian
# roulette; beyond 64 bounces nothing is left here).
import sys

import bpy

arguments = sys.argv[sys.argv.index("--") + 1:]
output, samples = arguments[:2]
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cycles = scene.cycles
cycles.device = "CPU"
cycles.samples = int(samples)
cycles.seed = int(arguments[2]) if len(arguments) > 2 else 0
cycles.use_adaptive_sampling = False
cycles.use_denoising = False
cycles.sample_clamp_direct = 0.0
cycles.sample_clamp_indirect = 0.0
cycles.blur_glossy = 0.0
cycles.caustics_reflective = True
cycles.caustics_refractive = True
for bounces in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                "transparent_max_bounces", "volume_bounces"):
    setattr(cycles, bounces, 64)
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = output
bpy.ops.render.render(write_still=True)
