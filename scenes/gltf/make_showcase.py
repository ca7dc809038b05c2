#!/usr/bin/env python3
"""Writes showcase.gltf: a small glTF 2.0 scene that exercises what foton reads from glTF and
that pbrt-v4 can render too once gltf_to_pbrt.py has converted it (pbrt-v4 has no glTF
reader), so the two renderers can be compared on one file.

In the file: a floor with a base colour texture under KHR_texture_transform (offset, rotation,
scale), a back wall under a tangent-space normal map, a smooth-shaded UV sphere used twice (a
rough gold metal and a red Lambert: KHR_materials_specular's specularFactor 0), a rough copper
box turned by a quaternion under a translated parent node, an emissive panel whose emission is
a texture with KHR_materials_emissive_strength, a point and a directional light
(KHR_lights_punctual) and a perspective camera placed by its node's rotation and translation.
Buffers are embedded as a base64 data URI; the two images are written beside it
(showcase_tiles.png: 4 x 4 tiles whose colours change along both axes, so a flipped or turned
lookup shows; showcase_normals.png: bumps tilted towards +v on average, so a wrong bitangent
sign shows as a darker wall under the lamp above).

Pure Python, deterministic: run from this folder, python3 make_showcase.py"""
import base64
import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "pbrt", "materials", "textures"))
from make_textures import png  # noqa: E402  (the repository's PNG writer)

TILES = "showcase_tiles.png"
NORMALS = "showcase_normals.png"
N = 64


def write_images():
    tiles, normals = [], []
    for j in range(N):  # j: row from the image's top
        trow, nrow = [], []
        for i in range(N):
            ti, tj = i // 16, j // 16
            # Mortar on both sides of every edge, so a repeating and a clamping lookup agree
            # at the image border (pbrt-v4 clamps an area light's image, glTF repeats).
            mortar = i % 16 in (0, 15) or j % 16 in (0, 15)
            rgb = (0.15, 0.15, 0.15) if mortar else (0.25 + 0.2 * ti, 0.3 + 0.15 * tj, 0.45)
            trow += [round(255 * c) for c in rgb]
            u, v = (i + 0.5) / N, 1.0 - (j + 0.5) / N
            n = (0.35 * math.sin(4 * math.pi * u), 0.15 + 0.35 * math.sin(4 * math.pi * v), 1.0)
            ln = math.sqrt(sum(c * c for c in n))
            nrow += [max(0, min(255, round((c / ln * 0.5 + 0.5) * 255))) for c in n]
        tiles.append(trow)
        normals.append(nrow)
    png(TILES, tiles, 8, 3)
    png(NORMALS, normals, 8, 3)


class Buffer:
    """One binary buffer; every accessor gets its own buffer view."""

    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def add(self, fmt, rows, kind, component, target=None, bounds=False):
        while len(self.data) % 4:
            self.data += b"\0"
        start = len(self.data)
        for row in rows:
            self.data += struct.pack("<" + fmt, *(row if isinstance(row, tuple) else (row,)))
        view = {"buffer": 0, "byteOffset": start, "byteLength": len(self.data) - start}
        if target:
            view["target"] = target
        self.views.append(view)
        acc = {"bufferView": len(self.views) - 1, "componentType": component,
               "count": len(rows), "type": kind}
        if bounds:
            acc["min"] = [min(r[i] for r in rows) for i in range(3)]
            acc["max"] = [max(r[i] for r in rows) for i in range(3)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def mesh(self, positions, normals, uvs, indices):
        attrs = {"POSITION": self.add("3f", positions, "VEC3", 5126, 34962, True),
                 "NORMAL": self.add("3f", normals, "VEC3", 5126, 34962)}
        if uvs:
            attrs["TEXCOORD_0"] = self.add("2f", uvs, "VEC2", 5126, 34962)
        return attrs, self.add("H", indices, "SCALAR", 5123, 34963)


def quad(corner, edge_u, edge_v, uv_scale=(1.0, 1.0)):
    """A quad from corner along two edges; its uv (glTF's: v runs down the image) puts the
    image upright when u runs right and v up the quad."""
    c = corner
    p = [c, tuple(c[i] + edge_u[i] for i in range(3)),
         tuple(c[i] + edge_u[i] + edge_v[i] for i in range(3)),
         tuple(c[i] + edge_v[i] for i in range(3))]
    n = (edge_u[1] * edge_v[2] - edge_u[2] * edge_v[1], edge_u[2] * edge_v[0] - edge_u[0] * edge_v[2],
         edge_u[0] * edge_v[1] - edge_u[1] * edge_v[0])
    ln = math.sqrt(sum(x * x for x in n))
    n = tuple(x / ln for x in n)
    su, sv = uv_scale
    uv = [(0.0, sv), (su, sv), (su, 0.0), (0.0, 0.0)]
    return p, [n] * 4, uv, [0, 1, 2, 0, 2, 3]


def uv_sphere(rings=24, segments=48):
    p, n, uv, idx = [], [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            d = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            p.append(d)
            n.append(d)
            uv.append((j / segments, i / rings))
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            if i > 0:
                idx += [a, b, a + 1]
            if i < rings - 1:
                idx += [a + 1, b, b + 1]
    return p, n, uv, idx


def box():
    """A unit cube centred on the origin, flat faces (4 vertices each)."""
    p, n, idx = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            normal = [0.0, 0.0, 0.0]
            normal[axis] = sign
            u = [0.0, 0.0, 0.0]
            u[(axis + 1) % 3] = 1.0
            v = [0.0, 0.0, 0.0]
            v[(axis + 2) % 3] = 1.0
            if sign < 0:
                u, v = v, u
            base = len(p)
            for a, b in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)):
                p.append(tuple(0.5 * normal[k] + a * u[k] + b * v[k] for k in range(3)))
                n.append(tuple(normal))
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return p, n, None, idx


def look_at_quaternion(eye, target):
    """The rotation that turns glTF's camera (looking down -z, y up) towards target."""
    f = [target[i] - eye[i] for i in range(3)]
    lf = math.sqrt(sum(x * x for x in f))
    z = [-x / lf for x in f]
    up = (0.0, 1.0, 0.0)
    x = [up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]]
    lx = math.sqrt(sum(t * t for t in x))
    x = [t / lx for t in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]
    w = math.sqrt(max(0.0, 1 + m[0][0] + m[1][1] + m[2][2])) / 2
    return [(m[2][1] - m[1][2]) / (4 * w), (m[0][2] - m[2][0]) / (4 * w),
            (m[1][0] - m[0][1]) / (4 * w), w]


def main():
    write_images()
    buf = Buffer()
    floor = buf.mesh(*quad((-3.0, 0.0, 2.5), (6.0, 0.0, 0.0), (0.0, 0.0, -5.0)))
    wall = buf.mesh(*quad((-3.0, 0.0, -2.5), (6.0, 0.0, 0.0), (0.0, 3.5, 0.0), (2.0, 1.0)))
    panel = buf.mesh(*quad((-0.6, 0.0, 0.0), (1.2, 0.0, 0.0), (0.0, 0.8, 0.0)))
    sphere = buf.mesh(*uv_sphere())
    cube = buf.mesh(*box())

    def prim(mesh, material):
        attrs, indices = mesh
        return {"primitives": [{"attributes": attrs, "indices": indices, "material": material}]}

    no_specular = {"KHR_materials_specular": {"specularFactor": 0.0}}
    materials = [
        {"name": "floor", "extensions": no_specular,
         "pbrMetallicRoughness": {
             "baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0,
             "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
                 "offset": [0.15, -0.1], "rotation": 0.35, "scale": [1.2, 1.0]}}}}},
        {"name": "wall", "extensions": no_specular,
         "normalTexture": {"index": 1},
         "pbrMetallicRoughness": {"baseColorFactor": [0.55, 0.6, 0.65, 1.0], "metallicFactor": 0.0}},
        {"name": "gold", "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 0.78, 0.34, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.45}},
        {"name": "red", "extensions": no_specular, "pbrMetallicRoughness": {
            "baseColorFactor": [0.7, 0.12, 0.08, 1.0], "metallicFactor": 0.0}},
        {"name": "copper", "pbrMetallicRoughness": {
            "baseColorFactor": [0.95, 0.64, 0.54, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.7}},
        {"name": "glow", "extensions": dict(no_specular, KHR_materials_emissive_strength={
            "emissiveStrength": 3.0}),
         "emissiveFactor": [1.0, 1.0, 1.0], "emissiveTexture": {"index": 0},
         "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0}},
    ]
    meshes = [prim(floor, 0), prim(wall, 1), prim(sphere, 2), prim(sphere, 3), prim(cube, 4),
              prim(panel, 5)]
    eye, target = (0.4, 1.7, 6.0), (0.0, 0.8, 0.0)
    s = math.sin(0.3)
    nodes = [
        {"name": "floor", "mesh": 0},
        {"name": "wall", "mesh": 1},
        {"name": "gold sphere", "mesh": 2, "translation": [-1.5, 0.7, 0.2], "scale": [0.7, 0.7, 0.7]},
        {"name": "red sphere", "mesh": 3, "translation": [1.6, 0.5, 0.6], "scale": [0.5, 0.5, 0.5]},
        {"name": "stand", "translation": [0.1, 0.0, -0.6], "children": [5]},
        {"name": "copper box", "mesh": 4, "translation": [0.0, 0.45, 0.0],
         "rotation": [0.0, s, 0.0, math.cos(0.3)], "scale": [0.9, 0.9, 0.9]},
        {"name": "panel", "mesh": 5, "translation": [0.0, 1.3, -2.45]},
        {"name": "lamp", "translation": [1.2, 3.0, 2.0],
         "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "sun", "rotation": look_at_quaternion((0.0, 0.0, 0.0), (-0.4, -1.0, -0.5)),
         "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"name": "camera", "camera": 0, "translation": list(eye),
         "rotation": look_at_quaternion(eye, target)},
    ]
    gltf = {
        "asset": {"version": "2.0", "generator": "scenes/gltf/make_showcase.py"},
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_specular",
                           "KHR_materials_emissive_strength", "KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.9, 0.8], "intensity": 4000.0},
            {"type": "directional", "color": [0.9, 0.95, 1.0], "intensity": 500.0}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3, 4, 6, 7, 8, 9]}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1}}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": TILES}, {"uri": NORMALS}],
        "buffers": [{"byteLength": len(buf.data), "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(bytes(buf.data)).decode()}],
        "bufferViews": buf.views,
        "accessors": buf.accessors,
    }
    with open("showcase.gltf", "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")


main()
