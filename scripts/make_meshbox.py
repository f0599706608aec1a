#!/usr/bin/env python3
"""Writes the mesh-sphere box of issue 75 (scenes/meshbox): a 2 x 2 x 2 box open at the
front, walls white 0.73, red (0.63, 0.065, 0.05) on the left and green (0.14, 0.45, 0.091)
on the right, a 0.5 x 0.5 quad light just under the ceiling emitting (12, 10, 7) from its
front (down), and two spheres of 5,120 triangles each (an icosahedron subdivided four
times, vertex normals radial; one unit sphere placed twice), white 0.73 and grey 0.5. The camera is at z = 3.6 looking
at the origin with a 40 degree field of view. scripts/cycles_meshbox.py builds the same
box in Blender from these files; scripts/bench_cycles.sh renders both.

    python3 scripts/make_meshbox.py [OUT_DIR]     (default: scenes/meshbox)
"""
import math
import os
import sys

# The spheres: the unit icosphere meshes/sphere.obj scaled by the radius and moved to the
# centre (scripts/cycles_meshbox.py imports this list).
SPHERES = [("white", (-0.45, -0.6, -0.25), 0.4, (0.73, 0.73, 0.73)),
           ("grey", (0.45, -0.6, 0.3), 0.4, (0.5, 0.5, 0.5))]
# The walls' albedos (meshes/NAME.obj) and the light's radiance.
WALLS = {"floor": (0.73, 0.73, 0.73), "ceiling": (0.73, 0.73, 0.73),
         "back": (0.73, 0.73, 0.73), "left": (0.63, 0.065, 0.05),
         "right": (0.14, 0.45, 0.091)}
RADIANCE = (12.0, 10.0, 7.0)


def icosphere(subdivisions):
    """Unit icosphere: vertices on the sphere, faces counter-clockwise seen from outside."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    vertices = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in vertices]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9),
             (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2),
             (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
             (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                m = [(p + q) / 2.0 for p, q in zip(vertices[a], vertices[b])]
                length = math.sqrt(sum(x * x for x in m))
                vertices.append(tuple(x / length for x in m))
                midpoints[key] = len(vertices) - 1
            return midpoints[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    return vertices, faces


def write_obj(path, vertices, faces, normals=None):
    with open(path, "w") as out:
        out.write("# Written by scripts/make_meshbox.py.\n")
        for v in vertices:
            out.write("v {:.7f} {:.7f} {:.7f}\n".format(*v))
        for n in normals or []:
            out.write("vn {:.7f} {:.7f} {:.7f}\n".format(*n))
        for face in faces:
            if normals:
                out.write("f " + " ".join(f"{i + 1}//{i + 1}" for i in face) + "\n")
            else:
                out.write("f " + " ".join(str(i + 1) for i in face) + "\n")


def quad(corners):
    """A quad as two triangles; its front is counter-clockwise."""
    return corners, [(0, 1, 2), (0, 2, 3)]


def main():
    if sys.argv[1:2] in (["-h"], ["--help"]):
        print(__doc__.strip())
        return
    here = os.path.dirname(os.path.abspath(__file__))
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "scenes", "meshbox")
    meshes = os.path.join(out_dir, "meshes")
    os.makedirs(meshes, exist_ok=True)
    # The walls face into the box.
    walls = {
        "floor": quad([(-1, -1, 1), (1, -1, 1), (1, -1, -1), (-1, -1, -1)]),
        "ceiling": quad([(-1, 1, -1), (1, 1, -1), (1, 1, 1), (-1, 1, 1)]),
        "back": quad([(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)]),
        "left": quad([(-1, -1, 1), (-1, -1, -1), (-1, 1, -1), (-1, 1, 1)]),
        "right": quad([(1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1)]),
        # Facing down, just under the ceiling.
        "light": quad([(-0.25, 0.999, -0.25), (0.25, 0.999, -0.25), (0.25, 0.999, 0.25),
                       (-0.25, 0.999, 0.25)]),
    }
    for name, (vertices, faces) in walls.items():
        write_obj(os.path.join(meshes, name + ".obj"), vertices, faces)
    unit, faces = icosphere(4)
    write_obj(os.path.join(meshes, "sphere.obj"), unit, faces, normals=unit)

    def mesh(name, bsdf, to_world=""):
        return (f'    <mesh type="obj">\n'
                f'        <string name="filename" value="meshes/{name}.obj"/>\n{to_world}'
                f'        {bsdf}\n    </mesh>\n')

    def diffuse(rgb):
        return f'<bsdf type="diffuse"><color name="albedo" value="{rgb}"/></bsdf>'

    colour = "{}, {}, {}".format
    scene = ['<?xml version="1.0" encoding="utf-8"?>\n',
             '<!-- The mesh-sphere box of issue 75, written by scripts/make_meshbox.py; '
             'scripts/bench_cycles.sh renders it against Cycles. -->\n<scene>\n',
             '    <default name="integrator" value="path_mis"/>\n',
             '    <default name="spp" value="64"/>\n    <default name="size" value="512"/>\n',
             '    <default name="sampler" value="sobol"/>\n    <default name="seed" value="0"/>\n',
             '    <default name="lightsampling" value="solidangle"/>\n',
             '    <default name="lightsampler" value="bvh"/>\n',
             '    <integrator type="$integrator"/>\n',
             '    <sampler type="$sampler">\n'
             '        <integer name="sampleCount" value="$spp"/>\n'
             '        <integer name="seed" value="$seed"/>\n    </sampler>\n',
             '    <camera type="perspective">\n'
             '        <transform name="toWorld">\n'
             '            <lookat origin="0, 0, 3.6" target="0, 0, 0" up="0, 1, 0"/>\n'
             '        </transform>\n'
             '        <float name="fov" value="40"/>\n'
             '        <integer name="width" value="$size"/>\n'
             '        <integer name="height" value="$size"/>\n'
             '        <rfilter type="box"/>\n    </camera>\n',
             '    <string name="lightSampler" value="$lightsampler"/>\n']
    for name, albedo in WALLS.items():
        scene.append(mesh(name, diffuse(colour(*albedo))))
    for _, center, radius, albedo in SPHERES:
        to_world = ('        <transform name="toWorld">\n'
                    f'            <scale value="{radius}"/>\n'
                    f'            <translate value="{colour(*center)}"/>\n'
                    '        </transform>\n')
        scene.append(mesh("sphere", diffuse(colour(*albedo)), to_world))
    scene.append(mesh("light", '<bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>\n'
                      '        <emitter type="area">\n'
                      f'            <color name="radiance" value="{colour(*RADIANCE)}"/>\n'
                      '            <string name="sampling" value="$lightsampling"/>\n'
                      '        </emitter>'))
    scene.append("</scene>\n")
    with open(os.path.join(out_dir, "meshbox.xml"), "w") as out:
        out.write("".join(scene))


if __name__ == "__main__":
    main()
