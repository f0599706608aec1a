#!/usr/bin/env python3
"""Writes the many-light benchmark scene: COUNT small lights (half spheres, half one-sided
triangles facing random ways) of powers spread over two decades, 1 to 3 m over a floor
with box occluders, as ETH's 1203-light variant of Veach's scene stresses light
selection. The camera, 0.9 m high and looking 31° down (the top of its view level) with a 60° field of view, sees
the floor and the boxes but no light: where a light is in view, the noise of the
pixels its edge crosses is the same whatever picks the lights, and would hide the
difference the benchmark is there to measure.

    scripts/make_many_lights.py OUTPUT_DIR [COUNT] [SEED]

writes OUTPUT_DIR/manylights.xml and its meshes (floor, box, triangle). Render it with
    nori -D spp=16 -D lightsampler=power OUTPUT_DIR/manylights.xml
(lightsampler: bvh, the default, or power; sampler, spp, size, seed, integrator as in the
other example scenes). The same COUNT and SEED give the same scene."""
import math
import os
import random
import sys


def write_obj(path, vertices, faces):
    with open(path, "w", encoding="utf-8") as out:
        for v in vertices:
            out.write("v {:.6f} {:.6f} {:.6f}\n".format(*v))
        for f in faces:
            out.write("f " + " ".join(str(i + 1) for i in f) + "\n")


def write_meshes(directory):
    # A 24 × 24 floor at y = 0, facing up; a unit box on the floor; a unit triangle
    # facing +z (its area √3/4 · 1² for edge length 1).
    write_obj(os.path.join(directory, "floor.obj"),
              [(-12, 0, -12), (-12, 0, 12), (12, 0, 12), (12, 0, -12)], [(0, 1, 2), (0, 2, 3)])
    corners = [(x, y, z) for x in (-0.5, 0.5) for y in (0, 1) for z in (-0.5, 0.5)]
    # Outward-facing quads of the box, by corner index (x·4 + y·2 + z).
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    write_obj(os.path.join(directory, "box.obj"), corners,
              [f for q in quads for f in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))])
    h = math.sqrt(3) / 2
    write_obj(os.path.join(directory, "triangle.obj"),
              [(-0.5, -h / 3, 0), (0.5, -h / 3, 0), (0, 2 * h / 3, 0)], [(0, 1, 2)])


def random_rotation(rng):
    """An axis and angle (degrees) turning +z to a uniformly random direction."""
    z = rng.uniform(-1.0, 1.0)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(max(0.0, 1.0 - z * z))
    d = (r * math.cos(phi), r * math.sin(phi), z)
    axis = (-d[1], d[0], 0.0)  # +z × d
    if math.hypot(axis[0], axis[1]) < 1e-6:
        axis = (1.0, 0.0, 0.0)
    return axis, math.degrees(math.acos(max(-1.0, min(1.0, z))))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    directory = sys.argv[1]
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    os.makedirs(directory, exist_ok=True)
    write_meshes(directory)
    rng = random.Random(seed)

    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             "<!-- {} small lights over a floor with boxes: written by "
             "scripts/make_many_lights.py (seed {}). -->".format(count, seed),
             "<scene>"]
    for name, value in (("integrator", "path_mis"), ("spp", "16"), ("size", "512"),
                        ("sampler", "independent"), ("seed", "0"), ("lightsampler", "bvh")):
        lines.append('    <default name="{}" value="{}"/>'.format(name, value))
    lines += ['    <string name="lightSampler" value="$lightsampler"/>',
              '    <integrator type="$integrator"/>',
              '    <sampler type="$sampler">',
              '        <integer name="sampleCount" value="$spp"/>',
              '        <integer name="seed" value="$seed"/>',
              "    </sampler>",
              '    <camera type="perspective">',
              '        <float name="fov" value="60"/>',
              '        <integer name="width" value="$size"/>',
              '        <integer name="height" value="$size"/>',
              '        <transform name="toWorld">',
              '            <lookat origin="0, 0.9, 10" target="0, 0.385, 9.143" up="0, 1, 0"/>',
              "        </transform>",
              "    </camera>",
              '    <mesh type="obj">',
              '        <string name="filename" value="floor.obj"/>',
              '        <bsdf type="diffuse"><color name="albedo" value="0.6"/></bsdf>',
              "    </mesh>"]
    for _ in range(12):
        sx, sy, sz = rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.5), rng.uniform(0.5, 2.0)
        lines += ['    <mesh type="obj">',
                  '        <string name="filename" value="box.obj"/>',
                  '        <transform name="toWorld">',
                  '            <scale value="{:.3f}, {:.3f}, {:.3f}"/>'.format(sx, sy, sz),
                  '            <rotate axis="0, 1, 0" angle="{:.1f}"/>'.format(rng.uniform(0, 90)),
                  '            <translate value="{:.3f}, 0, {:.3f}"/>'.format(
                      rng.uniform(-8, 8), rng.uniform(-8, 8)),
                  "        </transform>",
                  '        <bsdf type="diffuse"><color name="albedo" value="{:.2f}, {:.2f}, '
                  '{:.2f}"/></bsdf>'.format(*(rng.uniform(0.3, 0.8) for _ in range(3))),
                  "    </mesh>"]
    for i in range(count):
        # Power log-uniform over [0.03, 3] W, a colour near white.
        power = math.exp(rng.uniform(math.log(0.03), math.log(3.0)))
        tint = [rng.uniform(0.6, 1.0) for _ in range(3)]
        x, y, z = rng.uniform(-10, 10), rng.uniform(1.0, 3.0), rng.uniform(-10, 10)
        if i % 2 == 0:
            radius = rng.uniform(0.03, 0.08)
            area = 4.0 * math.pi * radius * radius
            radiance = power / (math.pi * area)
            lines += ['    <mesh type="sphere">',
                      '        <point name="center" value="{:.4f}, {:.4f}, {:.4f}"/>'.format(x, y, z),
                      '        <float name="radius" value="{:.4f}"/>'.format(radius)]
        else:
            edge = rng.uniform(0.1, 0.25)
            area = math.sqrt(3) / 4 * edge * edge
            radiance = power / (math.pi * area)
            axis, angle = random_rotation(rng)
            lines += ['    <mesh type="obj">',
                      '        <string name="filename" value="triangle.obj"/>',
                      '        <transform name="toWorld">',
                      '            <scale value="{:.4f}"/>'.format(edge),
                      '            <rotate axis="{:.5f}, {:.5f}, {:.5f}" angle="{:.3f}"/>'.format(
                          *axis, angle),
                      '            <translate value="{:.4f}, {:.4f}, {:.4f}"/>'.format(x, y, z),
                      "        </transform>"]
        lines += ['        <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>',
                  '        <emitter type="area"><color name="radiance" value="{:.4f}, {:.4f}, '
                  '{:.4f}"/></emitter>'.format(*(radiance * t for t in tint)),
                  "    </mesh>"]
    lines.append("</scene>")
    with open(os.path.join(directory, "manylights.xml"), "w", encoding="utf-8") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    if sys.argv[1:2] in (["-h"], ["--help"]):
        print(__doc__)
        sys.exit(0)
    main()
