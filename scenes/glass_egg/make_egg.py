#!/usr/bin/env python3
"""Writes egg.obj: a closed egg of revolution about +y, 1 unit tall, resting on y = 0.

The profile is an ellipse whose horizontal radius grows towards the blunt end:
r(y) = R * sqrt(1 - s^2) * (1 + k * s) with s = 2y - 1 in [-1, 1]. Vertex normals come from
the gradient of the implicit profile, so the glass refracts like a smooth egg.
Run: python3 make_egg.py > egg.obj
"""
import math

RINGS, SEGMENTS = 24, 48
R, K = 0.36, -0.12  # radius at the middle; k < 0 makes the lower end blunter


def radius(s):
    return R * math.sqrt(max(0.0, 1 - s * s)) * (1 + K * s)


def d_radius(s):
    root = math.sqrt(max(1e-12, 1 - s * s))
    return R * (-s / root * (1 + K * s) + root * K)


def main():
    vertices, normals = [], []
    for i in range(1, RINGS):
        s = -1 + 2 * i / RINGS  # poles excluded: they are added below
        r, y = radius(s), (s + 1) / 2
        dr_dy = 2 * d_radius(s)
        for j in range(SEGMENTS):
            phi = 2 * math.pi * j / SEGMENTS
            c, si = math.cos(phi), math.sin(phi)
            vertices.append((r * c, y, r * si))
            n = (c, -dr_dy, si)  # normal of the surface r(y) - rho = 0 points outwards
            length = math.sqrt(sum(v * v for v in n))
            normals.append(tuple(v / length for v in n))
    bottom, top = len(vertices) + 1, len(vertices) + 2
    vertices += [(0.0, 0.0, 0.0), (0.0, 1.0, 0.0)]
    normals += [(0.0, -1.0, 0.0), (0.0, 1.0, 0.0)]

    def index(ring, seg):
        return ring * SEGMENTS + seg % SEGMENTS + 1

    faces = []
    for ring in range(RINGS - 2):
        for seg in range(SEGMENTS):
            a, b = index(ring, seg), index(ring, seg + 1)
            c, d = index(ring + 1, seg + 1), index(ring + 1, seg)
            faces += [(a, d, c), (a, c, b)]
    last = RINGS - 2
    for seg in range(SEGMENTS):
        faces.append((bottom, index(0, seg), index(0, seg + 1)))
        faces.append((top, index(last, seg + 1), index(last, seg)))

    print("# egg of revolution written by make_egg.py")
    for v in vertices:
        print("v %.6f %.6f %.6f" % v)
    for n in normals:
        print("vn %.6f %.6f %.6f" % n)
    for f in faces:
        print("f " + " ".join("%d//%d" % (i, i) for i in f))


if __name__ == "__main__":
    main()
