#!/usr/bin/env python3
"""Writes the many-lights scene: a 40 x 40 plaza of stone blocks under 4,096 small lamps
(downward-facing triangles, 8 colours whose radiance spans 20x), for timing next event
estimation's light choice (light_selection="power|uniform|bvh"). The lamps are generated,
not committed (the OBJ is 350 KB); bench/many_lights runs this first.

    scripts/make_many_lights.py [--lamps 4096] [--out out/many-lights]

writes DIR/many-lights.xml, DIR/lamps.obj and DIR/lamps.mtl. The same seed gives the same
files on every machine (Python's random is specified to be reproducible).
"""
import argparse
import math
import os
import random

# name, Ke (radiance): warm, cold and coloured lamps, the strongest 20x the weakest.
LAMPS = [
    ("warm_dim", (2.0, 1.5, 0.9)),
    ("warm", (8.0, 6.0, 3.5)),
    ("warm_bright", (30.0, 22.0, 13.0)),
    ("cold", (4.0, 5.0, 7.0)),
    ("cold_bright", (16.0, 20.0, 28.0)),
    ("red", (12.0, 2.0, 1.5)),
    ("green", (2.0, 10.0, 3.0)),
    ("blue", (1.5, 3.0, 14.0)),
]
HALF = 20.0          # the plaza spans [-HALF, HALF] in x and z
LAMP_RADIUS = 0.15   # circumradius of a lamp triangle
BLOCKS = 48


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lamps", type=int, default=4096)
    ap.add_argument("--out", default="out/many-lights")
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    if args.lamps < 1:
        ap.error("--lamps must be at least 1")
    rnd = random.Random(args.seed)
    os.makedirs(args.out, exist_ok=True)

    lines = ["# scripts/make_many_lights.py --lamps %d --seed %d" % (args.lamps, args.seed),
             "mtllib lamps.mtl"]
    count = 0

    def vertex(x, y, z):
        lines.append("v %.3f %.3f %.3f" % (x, y, z))

    # Blocks: axis-aligned boxes standing on the plaza (5 faces, no bottom).
    lines.append("usemtl stone")
    for _ in range(BLOCKS):
        cx, cz = rnd.uniform(-HALF + 2, HALF - 2), rnd.uniform(-HALF + 2, HALF - 2)
        sx, sz, h = rnd.uniform(0.5, 1.6), rnd.uniform(0.5, 1.6), rnd.uniform(0.8, 2.2)
        for y in (0.0, h):
            for dx, dz in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                vertex(cx + dx * sx, y, cz + dz * sz)
        count += 8
        b = count - 7  # 1-based index of the first corner
        bottom, top = [b, b + 1, b + 2, b + 3], [b + 4, b + 5, b + 6, b + 7]
        lines.append("f %d %d %d %d" % (top[0], top[3], top[2], top[1]))
        for k in range(4):
            a0, a1 = bottom[k], bottom[(k + 1) % 4]
            t0, t1 = top[k], top[(k + 1) % 4]
            lines.append("f %d %d %d %d" % (a0, a1, t1, t0))

    # Lamps: small triangles facing down (corners counter-clockwise seen from above, so
    # their normal points at the ground), grouped by colour.
    by_colour = [[] for _ in LAMPS]
    for _ in range(args.lamps):
        by_colour[rnd.randrange(len(LAMPS))].append(
            (rnd.uniform(-HALF, HALF), rnd.uniform(2.5, 4.0), rnd.uniform(-HALF, HALF),
             rnd.uniform(0, 2 * math.pi)))
    for (name, _), lamps in zip(LAMPS, by_colour):
        if not lamps:
            continue
        lines.append("usemtl " + name)
        for x, y, z, a in lamps:
            for k in range(3):
                t = a + k * 2 * math.pi / 3
                vertex(x + LAMP_RADIUS * math.cos(t), y, z + LAMP_RADIUS * math.sin(t))
            count += 3
            lines.append("f %d %d %d" % (count - 2, count - 1, count))
    with open(os.path.join(args.out, "lamps.obj"), "w") as f:
        f.write("\n".join(lines) + "\n")

    mtl = ["newmtl stone", "Kd 0.55 0.55 0.5"]
    for name, ke in LAMPS:
        mtl += ["newmtl " + name, "Kd 0 0 0", "Ke %g %g %g" % ke]
    with open(os.path.join(args.out, "lamps.mtl"), "w") as f:
        f.write("\n".join(mtl) + "\n")

    xml = """<?xml version="1.0" encoding="UTF-8"?>
<!-- Written by scripts/make_many_lights.py: %d lamps (each triangle an emitter under
     light_selection="bvh") over a plaza of stone blocks. -->
<scene>
  <objects>
    <quad name="plaza"><corner x="-%g" y="0" z="-%g"/><edge1 x="0" y="0" z="%g"/><edge2 x="%g" y="0" z="0"/>
      <material type="lambert"><reflectance r="0.5" g="0.5" b="0.5"/></material></quad>
    <triangle_mesh src="lamps.obj" smooth="false"/>
  </objects>
  <film width="320" height="240"/>
  <renderer type="path" spp="16" max_depth="5" light_selection="bvh"/>
  <camera fov="45"><eye x="0" y="9" z="-27"/><target x="0" y="0" z="1"/></camera>
</scene>
""" % (args.lamps, HALF, HALF, 2 * HALF, 2 * HALF)
    with open(os.path.join(args.out, "many-lights.xml"), "w") as f:
        f.write(xml)


if __name__ == "__main__":
    main()
