# Exports a .blend file's scene for nori from the command line:
#   blender -b file.blend --python blender/export.py -- out.xml [--spp N]
#       [--integrator NAME] [--max-depth N]
# Prints the exporter's warnings (what it could not map, naming the object), one per line
# prefixed "nori-export: warning:", and exits non-zero on an error.
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import io_scene_nori  # noqa: E402

arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser(prog="blender -b FILE.blend --python blender/export.py --")
parser.add_argument("output", help="the scene file to write (meshes/ and textures/ beside it)")
parser.add_argument("--spp", type=int, default=64, help="samples per pixel (default 64)")
parser.add_argument("--integrator", default=None,
                    help="default: path_mis, or volpath when the scene has volumes")
parser.add_argument("--max-depth", type=int, default=-1,
                    help="the integrator's maxDepth (default: the integrator's own)")
options = parser.parse_args(arguments)
try:
    warnings = io_scene_nori.export_scene(bpy.context, options.output, options.spp,
                                          options.integrator, options.max_depth)
except Exception as error:  # report and fail, instead of Blender's traceback and status 0
    print(f"nori-export: error: {error}", file=sys.stderr)
    sys.exit(1)
for warning in warnings:
    print(f"nori-export: warning: {warning}")
print(f"nori-export: wrote {options.output} ({len(warnings)} warnings)")
