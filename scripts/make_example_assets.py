#!/usr/bin/env python3
"""Writes the small assets of the example scenes that exercise mesh files, textures and the
environment light (scenes/env-spheres.xml, scenes/textured-meshes.xml), all made here:

  scenes/meshes/sky.hdr       a 128 x 64 lat-long sky (Radiance RGBE): a sun, a blue
                              gradient and a darker ground, so importance sampling matters
  scenes/meshes/tiles.png     a 64 x 64 sRGB tile texture
  scenes/meshes/crate.obj/mtl a cube with uv, its MTL naming the texture and a Phong lid
  scenes/meshes/gem.gltf      an octahedron in glTF 2.0 (embedded buffer), a metallic and
                              an emissive material on its two halves
  scenes/meshes/smoke.raw     a 32^3 density grid (little-endian float32, x fastest): a
                              plume of a few soft blobs with a noisy edge (scenes/smoke.xml)
  scenes/meshes/smoke.vdb     the same samples as an OpenVDB fog volume over the unit cube
  scenes/meshes/smoke.nvdb    and as NanoVDB (pbrt-v4's format), by nanovdb_convert
                              (scenes/pbrt/media/smoke_vdb.pbrt); needs python3-openvdb and
                              libnanovdb-tools, which scripts/bootstrap installs

    scripts/make_example_assets.py        (from the repository root)
"""
import base64
import json
import math
import struct
import subprocess
import zlib

OUT = "scenes/meshes/"


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes([0, 0, 0, 0])
    e = math.frexp(m)[1]
    s = 256.0 / (2.0 ** e)
    return bytes([int(r * s), int(g * s), int(b * s), e + 128])


def sky():
    w, h = 128, 64
    sun_dir = (math.cos(0.6) * math.cos(1.0), math.sin(0.6), math.cos(0.6) * math.sin(1.0))
    px = bytearray()
    for y in range(h):
        theta = math.pi * (y + 0.5) / h  # from the map's up (+y in the scenes)
        for x in range(w):
            phi = 2 * math.pi * (x + 0.5) / w
            d = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            up = d[1]
            if up > 0:
                c = (0.25 + 0.35 * (1 - up), 0.45 + 0.35 * (1 - up), 0.9)
            else:
                c = (0.18, 0.16, 0.14)
            cos_sun = sum(a * b for a, b in zip(d, sun_dir))
            if cos_sun > math.cos(0.09):
                c = (600.0, 560.0, 480.0)
            px += rgbe(*c)
    with open(OUT + "sky.hdr", "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        f.write(bytes(px))


def png(path, w, h, pixel):
    raw = b"".join(b"\x00" + bytes(c for x in range(w) for c in pixel(x, y)) for y in range(h))

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def tiles(x, y):
    if x % 16 == 0 or y % 16 == 0:
        return (200, 200, 190)
    return (180, 70, 40) if ((x // 16) + (y // 16)) % 2 == 0 else (60, 110, 170)


def crate():
    # A unit cube, each face with its own uv square; the top is "lid" (Phong).
    faces = [((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
             ((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
             ((0, -1, 0), (1, 0, 0), (0, 0, -1)), ((0, 1, 0), (1, 0, 0), (0, 0, 1))]
    v, vt, vn, f_side, f_top = [], [], [], [], []
    for i, (n, u, w) in enumerate(faces):
        base = len(v)
        for (a, b) in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            v.append(tuple(0.5 * (n[k] + a * u[k] + b * w[k]) for k in range(3)))
            vt.append(((a + 1) / 2, (b + 1) / 2))
        vn.append(n)
        face = " ".join("%d/%d/%d" % (base + k + 1, base + k + 1, i + 1) for k in range(4))
        (f_top if i == 5 else f_side).append("f " + face)
    with open(OUT + "crate.obj", "w") as f:
        f.write("# made by scripts/make_example_assets.py\nmtllib crate.mtl\n")
        f.writelines("v %g %g %g\n" % p for p in v)
        f.writelines("vt %g %g\n" % t for t in vt)
        f.writelines("vn %g %g %g\n" % n for n in vn)
        f.write("usemtl tiles\n" + "\n".join(f_side) + "\nusemtl lid\n" + "\n".join(f_top) + "\n")
    with open(OUT + "crate.mtl", "w") as f:
        f.write("# made by scripts/make_example_assets.py\n"
                "newmtl tiles\nKd 1 1 1\nmap_Kd tiles.png\nillum 1\n"
                "newmtl lid\nKd 0.35 0.3 0.25\nKs 0.4 0.4 0.4\nNs 80\nillum 2\n")


def gem():
    top = [(1, 0, 0), (0, 0, 1), (-1, 0, 0), (0, 0, -1)]
    pos, idx_up, idx_down = [], [], []
    for i in range(4):
        a, b = top[i], top[(i + 1) % 4]
        for tri, lst in (((b, a, (0, 1.4, 0)), idx_up), ((a, b, (0, -1.4, 0)), idx_down)):
            base = len(pos)
            pos.extend(tri)
            lst.extend([base, base + 1, base + 2])
    pbuf = b"".join(struct.pack("<3f", *p) for p in pos)
    ibuf = struct.pack("<%dH" % len(idx_up), *idx_up) + struct.pack("<%dH" % len(idx_down), *idx_down)
    buf = pbuf + ibuf
    lo = [min(p[k] for p in pos) for k in range(3)]
    hi = [max(p[k] for p in pos) for k in range(3)]
    g = {
        "asset": {"version": "2.0", "generator": "scripts/make_example_assets.py"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "rotation": [0, math.sin(0.2), 0, math.cos(0.2)]}],
        "meshes": [{"primitives": [
            {"attributes": {"POSITION": 0}, "indices": 1, "material": 0},
            {"attributes": {"POSITION": 0}, "indices": 2, "material": 1}]}],
        "materials": [
            {"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.34, 1],
                                                      "metallicFactor": 1, "roughnessFactor": 0.35}},
            {"name": "glow", "emissiveFactor": [1, 0.35, 0.1],
             "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.1, 1], "metallicFactor": 0}}],
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pbuf)},
                        {"buffer": 0, "byteOffset": len(pbuf), "byteLength": len(ibuf)}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "byteOffset": 0, "componentType": 5123, "count": 12, "type": "SCALAR"},
            {"bufferView": 1, "byteOffset": 24, "componentType": 5123, "count": 12, "type": "SCALAR"}],
    }
    with open(OUT + "gem.gltf", "w") as f:
        json.dump(g, f, indent=1)


def smoke():
    n = 32
    # Blobs along a rising, leaning column, each (centre x, y, z, radius) in [0, 1]^3.
    blobs = [(0.5, 0.16, 0.5, 0.27), (0.52, 0.35, 0.48, 0.28), (0.57, 0.55, 0.5, 0.28),
             (0.63, 0.72, 0.53, 0.25), (0.67, 0.86, 0.55, 0.2)]
    out = bytearray()
    for z in range(n):
        for y in range(n):
            for x in range(n):
                p = ((x + 0.5) / n, (y + 0.5) / n, (z + 0.5) / n)
                d = 0.0
                for (cx, cy, cz, r) in blobs:
                    q = ((p[0] - cx) ** 2 + (p[1] - cy) ** 2 + (p[2] - cz) ** 2) / (r * r)
                    d += max(0.0, 1.0 - q) ** 2
                # A deterministic ripple so the edge is not smooth.
                d *= 0.75 + 0.25 * math.sin(23 * p[0] + 7 * math.sin(17 * p[1])) * math.cos(19 * p[2])
                out += struct.pack("<f", max(0.0, d))
    with open(OUT + "smoke.raw", "wb") as f:
        f.write(bytes(out))
    smoke_vdb(n, out)


def smoke_vdb(n, raw):
    import numpy
    import pyopenvdb
    # The raw file is x fastest; OpenVDB's array is indexed [x][y][z].
    a = numpy.frombuffer(bytes(raw), dtype="<f4").reshape(n, n, n).transpose(2, 1, 0)
    g = pyopenvdb.FloatGrid()
    g.name = "density"
    g.gridClass = pyopenvdb.GridClass.FOG_VOLUME
    g.copyFromArray(numpy.ascontiguousarray(a))  # zero samples stay inactive background
    # Voxel i's centre at (i + 0.5) / n: the raw grid's sample centres over the unit cube.
    t = pyopenvdb.createLinearTransform(1.0 / n)
    t.translate((0.5 / n, 0.5 / n, 0.5 / n))
    g.transform = t
    pyopenvdb.write(OUT + "smoke.vdb", [g])
    subprocess.run(["nanovdb_convert", "-f", OUT + "smoke.vdb", OUT + "smoke.nvdb"], check=True,
                   stdout=subprocess.DEVNULL)


sky()
png(OUT + "tiles.png", 64, 64, tiles)
crate()
gem()
smoke()
