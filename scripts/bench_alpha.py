#!/usr/bin/env python3
"""The cost of alpha-masked geometry: a cloud of LEAVES cut-out leaves (quads whose alpha
mask, a 64 x 64 float image, is a disc of radius 0.45 with a notch: 57 % of the quad)
above an opaque ground of 80,000 triangles, under a sun and a sky, rendered by path_mis
(maxDepth 5, 256 x 256, SPP samples a pixel, all cores). Every ray through the cloud
meets masked candidates the BVH has to ask, and every ray to the ground meets opaque ones
that it should not. Each build renders the scene ROUNDS times, interleaved with the other
builds; prints per build the render time ("Done in") as median and range, and the rays a
second of the median render.

    python3 scripts/bench_alpha.py [--leaves N] [--spp S] [--rounds R] BUILD_DIR...
        (defaults: 4000 leaves, 16 spp, 3 rounds; BUILD_DIR holds the `nori` program)
"""
import argparse
import math
import os
import random
import re
import statistics
import struct
import subprocess
import sys
import tempfile


def write_mask(path, size=64):
    """A leaf's opacity: 1 inside a disc of radius 0.45 (uv units) about the centre, less a
    wedge notch at the top; 0 elsewhere. A PFM: linear floats, bottom row first."""
    rows = []
    for y in range(size):
        for x in range(size):
            u, v = (x + 0.5) / size - 0.5, (y + 0.5) / size - 0.5
            inside = u * u + v * v < 0.45 * 0.45 and not (v > 0.1 and abs(u) < 0.5 * v)
            rows.append(1.0 if inside else 0.0)
    with open(path, "wb") as out:
        out.write(b"PF\n%d %d\n-1.0\n" % (size, size))
        for value in rows:
            out.write(struct.pack("<3f", value, value, value))


def write_leaves(path, count, seed=7):
    """`count` quads of side 0.12, each with uv over [0, 1]^2, at random positions in the
    box [-1, 1] x [-0.6, 1] x [-1, 1] with random orientations."""
    generator = random.Random(seed)
    with open(path, "w") as out:
        out.write("# Written by scripts/bench_alpha.py.\n")
        for i in range(count):
            centre = (generator.uniform(-1, 1), generator.uniform(-0.6, 1),
                      generator.uniform(-1, 1))
            # Two random orthogonal unit vectors spanning the leaf.
            a = [generator.gauss(0, 1) for _ in range(3)]
            length = math.sqrt(sum(x * x for x in a))
            a = [x / length for x in a]
            b = [generator.gauss(0, 1) for _ in range(3)]
            dot = sum(p * q for p, q in zip(a, b))
            b = [q - dot * p for p, q in zip(a, b)]
            length = math.sqrt(sum(x * x for x in b))
            b = [0.06 * x / length for x in b]
            a = [0.06 * x for x in a]
            for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [c + su * x + sv * y for c, x, y in zip(centre, a, b)]
                out.write("v %.6f %.6f %.6f\n" % tuple(p))
            out.write("vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n")
            first = 4 * i + 1
            out.write("f %d/%d %d/%d %d/%d\n" % (first, first, first + 1, first + 1,
                                                  first + 2, first + 2))
            out.write("f %d/%d %d/%d %d/%d\n" % (first, first, first + 2, first + 2,
                                                  first + 3, first + 3))


def write_ground(path, cells=200):
    """A square of side 6 at y = -0.8 in cells x cells quads (two triangles each)."""
    with open(path, "w") as out:
        out.write("# Written by scripts/bench_alpha.py.\n")
        for j in range(cells + 1):
            for i in range(cells + 1):
                out.write("v %.5f -0.8 %.5f\n" % (-3 + 6 * i / cells, -3 + 6 * j / cells))
        for j in range(cells):
            for i in range(cells):
                a = j * (cells + 1) + i + 1
                out.write("f %d %d %d\nf %d %d %d\n" % (a, a + cells + 1, a + 1,
                                                          a + 1, a + cells + 1, a + cells + 2))


SCENE = """<scene>
    <integrator type="path_mis"><integer name="maxDepth" value="5"/></integrator>
    <sampler type="sobol"><integer name="sampleCount" value="{spp}"/></sampler>
    <camera type="perspective">
        <transform name="toWorld"><lookat origin="0, 1.2, 3.2" target="0, 0, 0" up="0, 1, 0"/></transform>
        <float name="fov" value="50"/>
        <integer name="width" value="256"/><integer name="height" value="256"/>
    </camera>
    <emitter type="directional"><vector name="direction" value="-0.3, -1, -0.4"/>
        <color name="irradiance" value="3, 2.8, 2.5"/></emitter>
    <emitter type="constant"><color name="radiance" value="0.3, 0.35, 0.45"/></emitter>
    <mesh type="obj"><string name="filename" value="ground.obj"/>
        <bsdf type="diffuse"><color name="albedo" value="0.5, 0.45, 0.4"/></bsdf></mesh>
    <mesh type="obj"><string name="filename" value="leaves.obj"/>
        <texture type="image" name="alpha"><string name="filename" value="leaf.pfm"/>
            <string name="filter" value="nearest"/></texture>
        <bsdf type="twosided"><bsdf type="diffuse"><color name="albedo" value="0.2, 0.5, 0.1"/></bsdf></bsdf>
    </mesh>
</scene>
"""


def render(nori, scene, output):
    """Renders once; returns (seconds, rays a second) from nori's "Done in" line."""
    result = subprocess.run([nori, "--no-progress", "-o", output, scene],
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("%s failed (exit %d):\n%s" % (nori, result.returncode, result.stderr[-2000:]))
    log = result.stdout + result.stderr
    done = re.search(r"Done in ([0-9.]+) (ms|s) .*?([0-9.]+) M rays/s", log)
    if not done:
        sys.exit("no 'Done in' line from %s:\n%s" % (nori, log[-2000:]))
    seconds = float(done.group(1)) / (1000.0 if done.group(2) == "ms" else 1.0)
    return seconds, float(done.group(3))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("builds", nargs="+", metavar="BUILD_DIR")
    parser.add_argument("--leaves", type=int, default=4000)
    parser.add_argument("--spp", type=int, default=16)
    parser.add_argument("--rounds", type=int, default=3)
    arguments = parser.parse_args()
    with tempfile.TemporaryDirectory() as directory:
        write_mask(os.path.join(directory, "leaf.pfm"))
        write_leaves(os.path.join(directory, "leaves.obj"), arguments.leaves)
        write_ground(os.path.join(directory, "ground.obj"))
        scene = os.path.join(directory, "foliage.xml")
        with open(scene, "w") as out:
            out.write(SCENE.format(spp=arguments.spp))
        times = {build: [] for build in arguments.builds}
        rates = {build: [] for build in arguments.builds}
        for _ in range(arguments.rounds):
            for build in arguments.builds:
                seconds, rate = render(os.path.join(build, "nori"), scene,
                                       os.path.join(directory, "out"))
                times[build].append(seconds)
                rates[build].append(rate)
        print("build  render time (s), median (range)  M rays/s (median render)")
        for build in arguments.builds:
            median = statistics.median(times[build])
            rate = rates[build][times[build].index(median)] if median in times[build] else \
                statistics.median(rates[build])
            print("%s  %.3f (%.3f-%.3f)  %.2f" % (build, median, min(times[build]),
                                                  max(times[build]), rate))


if __name__ == "__main__":
    main()
