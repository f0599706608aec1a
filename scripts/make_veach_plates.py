#!/usr/bin/env python3
"""Writes the four plates of Veach's multiple-importance-sampling test scene
(Veach 1997, fig. 9.4) as OBJ quads into scenes/veach/: each plate is tilted so
that the camera sees the row of lights mirrored in it (its normal is the half vector
between the directions to the camera and to the centre of the lights)."""
import math
import os
import sys

CAMERA = (0.0, 2.0, 15.0)
LIGHTS_CENTRE = (0.0, 1.5, -1.0)
PLATE_CENTRES = [(0.0, -1.95, 0.25), (0.0, -2.45, 1.45), (0.0, -2.9, 2.7), (0.0, -3.3, 4.0)]
HALF_WIDTH, HALF_DEPTH = 4.0, 0.5


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def scale(a, s):
    return tuple(x * s for x in a)


def normalize(a):
    n = math.sqrt(sum(x * x for x in a))
    return tuple(x / n for x in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def main():
    folder = os.path.join(os.path.dirname(__file__), "..", "scenes", "veach")
    for index, centre in enumerate(PLATE_CENTRES):
        normal = normalize(add(normalize(sub(CAMERA, centre)), normalize(sub(LIGHTS_CENTRE, centre))))
        across = (1.0, 0.0, 0.0)
        along = normalize(cross(normal, across))  # in the plate, perpendicular to x
        corners = [add(add(centre, scale(across, sx * HALF_WIDTH)), scale(along, sy * HALF_DEPTH))
                   for sx, sy in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]
        # Wind the quad so that (p1 − p0) × (p2 − p0) points along the normal.
        e1, e2 = sub(corners[1], corners[0]), sub(corners[2], corners[0])
        if sum(a * b for a, b in zip(cross(e1, e2), normal)) < 0:
            corners.reverse()
        with open(os.path.join(folder, f"plate{index + 1}.obj"), "w") as out:
            out.write(f"# Veach MIS plate {index + 1}, normal {tuple(round(x, 4) for x in normal)}\n")
            for c in corners:
                out.write("v {:.6f} {:.6f} {:.6f}\n".format(*c))
            out.write("f 1 2 3 4\n")


if __name__ == "__main__":
    if sys.argv[1:2] in (["-h"], ["--help"]):
        print(__doc__)
        sys.exit(0)
    main()
