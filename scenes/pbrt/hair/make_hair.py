#!/usr/bin/env python3
"""Writes swatches.pbrt's strands (strands.pbrt): three swatches of wavy hair hanging in front
of a wall, 300 strands each, every strand a cubic B-spline of 7 points drawn as a flat curve
0.012 wide tapering to 0.006 (pure Python, a fixed seed, so the file is the same every run).
Run from this folder: python3 make_hair.py"""
import math
import random

random.seed(36)
SWATCHES = [(-1.3, "blond"), (0.0, "brown"), (1.3, "red")]
lines = []
for x0, material in SWATCHES:
    lines.append(f'AttributeBegin\n  NamedMaterial "{material}"')
    for _ in range(300):
        x = x0 + random.uniform(-0.45, 0.45)
        z = random.uniform(-0.15, 0.15)
        phase = random.uniform(0, 2 * math.pi)
        amp = random.uniform(0.02, 0.06)
        pts = []
        for k in range(7):
            y = 2.3 - k * 0.36 + random.uniform(-0.01, 0.01)
            px = x + amp * math.sin(phase + k * 1.3) + 0.02 * k * (x - x0)
            pz = z + amp * math.cos(phase + k * 1.1)
            pts.append(f"{px:.3f} {y:.3f} {pz:.3f}")
        lines.append('  Shape "curve" "string basis" "bspline" "string type" "flat"'
                     f' "float width0" 0.012 "float width1" 0.006 "point3 P" [ {" ".join(pts)} ]')
    lines.append("AttributeEnd")
with open("strands.pbrt", "w") as f:
    f.write("# Made by make_hair.py: do not edit.\n" + "\n".join(lines) + "\n")
