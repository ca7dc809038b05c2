#!/usr/bin/env python3
"""Writes a (p, q) torus-knot tube as an OBJ: the project's own ~4K-triangle low-poly mesh
for the brute-force vs grid comparison (the thesis used a 3,936-triangle monkey).

    scripts/make_torus_knot.py > scenes/meshes/torus-knot.obj
"""
import math
import sys

P, Q = 2, 3          # winds P times around the axis, Q times through the hole
SEGMENTS, SIDES = 128, 16   # 128 * 16 * 2 = 4096 triangles
R, r, TUBE = 1.0, 0.4, 0.16


def curve(t):
    phi = t * 2 * math.pi
    rad = R + r * math.cos(Q * phi)
    return (rad * math.cos(P * phi), r * math.sin(Q * phi), rad * math.sin(P * phi))


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    length = math.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2)
    return (a[0] / length, a[1] / length, a[2] / length)


out = sys.stdout
out.write(f"# ({P},{Q}) torus knot, {SEGMENTS}x{SIDES} tube, {2 * SEGMENTS * SIDES} triangles\n")
for i in range(SEGMENTS):
    t = i / SEGMENTS
    c = curve(t)
    tangent = norm(sub(curve(t + 1e-4), curve(t - 1e-4)))
    normal = norm(cross(tangent, (0.0, 1.0, 0.0)))
    binormal = cross(tangent, normal)
    for j in range(SIDES):
        a = 2 * math.pi * j / SIDES
        ca, sa = math.cos(a) * TUBE, math.sin(a) * TUBE
        p = tuple(c[k] + ca * normal[k] + sa * binormal[k] for k in range(3))
        out.write("v %.6f %.6f %.6f\n" % p)
for i in range(SEGMENTS):
    for j in range(SIDES):
        a = i * SIDES + j + 1
        b = ((i + 1) % SEGMENTS) * SIDES + j + 1
        c = ((i + 1) % SEGMENTS) * SIDES + (j + 1) % SIDES + 1
        d = i * SIDES + (j + 1) % SIDES + 1
        out.write(f"f {a} {b} {c}\nf {a} {c} {d}\n")
