#!/usr/bin/env python3
"""Converts a glTF 2.0 file (.gltf with embedded or external buffers) to pbrt-v4's scene format,
for the glTF models that have a pbrt-v4 equivalent, so that pbrt-v4 (which reads no glTF) can
render what foton renders from the glTF itself. Written from the glTF 2.0 specification, not
from foton's reader, so the comparison checks foton's reading of the file.

What it converts, and how:
- node matrix or translation/rotation/scale, composed down the hierarchy; meshes written in
  world space (positions; normals by the inverse transpose), TEXCOORD_0 with any
  KHR_texture_transform of the material baked in (uv' = T R S uv), then v flipped (glTF's v
  runs down the image, pbrt's up);
- materials: metallicFactor 1 -> "conductor" with "reflectance" = baseColorFactor and
  alpha = roughnessFactor^2 ("remaproughness" false); metallicFactor 0 with
  KHR_materials_specular's specularFactor 0 -> "diffuse" (baseColorFactor, times
  baseColorTexture as an sRGB "imagemap" when there is one); normalTexture -> "normalmap";
  emissiveFactor (x KHR_materials_emissive_strength, x emissiveTexture) -> a "diffuse" area
  light on the primitive;
- KHR_lights_punctual point and directional lights: intensity / 683 (candela to W/sr, lux to
  W/m^2, the reading foton uses) times colour, as "point" I and "distant" L;
- the first perspective camera: pbrt's left-handed camera looks down +z, so the view is
  mirrored (Scale -1 1 1) before its LookAt; "fov" is yfov (the shorter side is the vertical
  one when aspectRatio >= 1).
Anything else (a metal-dielectric mix, a texture on a metal, spot lights, texCoord 1, ...) is
an error naming it: this converter never approximates.

Usage: gltf_to_pbrt.py model.gltf out.pbrt [--width W] [--spp N] [--maxdepth D]"""
import argparse
import base64
import json
import math
import os
import struct
import sys

LUMENS_PER_WATT = 683.0


def fail(what):
    sys.exit(f"gltf_to_pbrt: {what}")


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def node_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    t = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = node.get("scale", [1, 1, 1])
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + \
        [[0, 0, 0, 1]]


def apply(m, p, w):
    return [sum(m[i][k] * p[k] for k in range(3)) + m[i][3] * w for i in range(3)]


def inverse3(m):
    a = [row[:3] for row in m[:3]]
    det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    inv = [[0.0] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(3):
            r = [k for k in range(3) if k != j]
            c = [k for k in range(3) if k != i]
            minor = a[r[0]][c[0]] * a[r[1]][c[1]] - a[r[0]][c[1]] * a[r[1]][c[0]]
            inv[i][j] = (-1) ** (i + j) * minor / det
    return inv


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


class Model:
    def __init__(self, path):
        self.folder = os.path.dirname(os.path.abspath(path))
        with open(path) as f:
            self.g = json.load(f)
        self.buffers = []
        for b in self.g["buffers"]:
            uri = b["uri"]
            if uri.startswith("data:"):
                self.buffers.append(base64.b64decode(uri.split(",", 1)[1]))
            else:
                with open(os.path.join(self.folder, uri), "rb") as f:
                    self.buffers.append(f.read())

    def accessor(self, index):
        a = self.g["accessors"][index]
        view = self.g["bufferViews"][a["bufferView"]]
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
        fmt = {5126: "f", 5125: "I", 5123: "H", 5121: "B"}[a["componentType"]]
        size = struct.calcsize(fmt)
        stride = view.get("byteStride", size * width)
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        data = self.buffers[view["buffer"]]
        return [struct.unpack_from("<" + fmt * width, data, start + i * stride)
                for i in range(a["count"])]

    def image_path(self, texture_info):
        if texture_info.get("texCoord", 0) != 0:
            fail("a texture on TEXCOORD_1")
        tex = self.g["textures"][texture_info["index"]]
        uri = self.g["images"][tex["source"]]["uri"]
        if uri.startswith("data:"):
            fail("an embedded image (write it to a file first)")
        return uri


def uv_transform(info):
    """KHR_texture_transform's matrix T R S (rows of a 3 x 3)."""
    t = info.get("extensions", {}).get("KHR_texture_transform")
    if not t:
        return None
    if t.get("texCoord", 0) != 0:
        fail("KHR_texture_transform texCoord")
    ox, oy = t.get("offset", [0, 0])
    r = t.get("rotation", 0.0)
    sx, sy = t.get("scale", [1, 1])
    c, s = math.cos(r), math.sin(r)
    # T = [1 0 ox; 0 1 oy], R = [c s; -s c], S = diag(sx, sy): T R S.
    return [[c * sx, s * sy, ox], [-s * sx, c * sy, oy]]


def material_texture_infos(m):
    pbr = m.get("pbrMetallicRoughness", {})
    infos = [pbr.get(k) for k in ("baseColorTexture", "metallicRoughnessTexture")]
    infos += [m.get(k) for k in ("normalTexture", "emissiveTexture", "occlusionTexture")]
    return [i for i in infos if i]


def pbrt_material(model, m):
    """pbrt-v4 lines for glTF material m: (material line, area light line or None)."""
    name = m.get("name", "?")
    pbr = m.get("pbrMetallicRoughness", {})
    base = pbr.get("baseColorFactor", [1, 1, 1, 1])[:3]
    metallic = pbr.get("metallicFactor", 1.0)
    roughness = pbr.get("roughnessFactor", 1.0)
    exts = m.get("extensions", {})
    known = {"KHR_materials_specular", "KHR_materials_emissive_strength"}
    if set(exts) - known:
        fail(f"material {name}: extensions {sorted(set(exts) - known)}")
    if "metallicRoughnessTexture" in pbr or "occlusionTexture" in m:
        fail(f"material {name}: metallic-roughness or occlusion texture")
    if m.get("alphaMode", "OPAQUE") != "OPAQUE":
        fail(f"material {name}: alphaMode")
    rgb = " ".join(f"{c:.6g}" for c in base)
    if metallic == 1.0:
        if "baseColorTexture" in pbr:
            fail(f"material {name}: a textured metal")
        line = (f'Material "conductor" "rgb reflectance" [ {rgb} ] '
                f'"float roughness" {roughness * roughness:.6g} "bool remaproughness" false')
    elif metallic == 0.0 and exts.get("KHR_materials_specular", {}).get("specularFactor") == 0:
        if "baseColorTexture" in pbr:
            if not (base[0] == base[1] == base[2]):
                fail(f"material {name}: a coloured factor on a texture (pbrt's scale is a float)")
            line = f'Material "diffuse" "texture reflectance" "{name}-base"'
        else:
            line = f'Material "diffuse" "rgb reflectance" [ {rgb} ]'
    else:
        fail(f"material {name}: metallic {metallic} with a dielectric reflection has no pbrt-v4 "
             "equivalent (use metallic 1, or 0 with KHR_materials_specular specularFactor 0)")
    if "normalTexture" in m:
        if m["normalTexture"].get("scale", 1.0) != 1.0:
            fail(f"material {name}: normalTexture scale")
        line += f' "string normalmap" "{model.image_path(m["normalTexture"])}"'
    light = None
    emissive = m.get("emissiveFactor", [0, 0, 0])
    strength = exts.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0)
    if any(emissive):
        if "emissiveTexture" in m:
            if not (emissive[0] == emissive[1] == emissive[2]):
                fail(f"material {name}: a coloured emissive factor on a texture")
            light = (f'AreaLightSource "diffuse" "string filename" '
                     f'"{model.image_path(m["emissiveTexture"])}" "float scale" '
                     f'{emissive[0] * strength:.6g}')
        else:
            le = " ".join(f"{c * strength:.6g}" for c in emissive)
            light = f'AreaLightSource "diffuse" "rgb L" [ {le} ]'
    return line, light


def convert(path, out, width, spp, maxdepth):
    model = Model(path)
    g = model.g
    lines = [f"# Made by gltf_to_pbrt.py from {os.path.basename(path)}: do not edit."]
    world = []
    textures = []
    camera = None
    lights = g.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])

    def visit(index, parent):
        nonlocal camera
        node = g["nodes"][index]
        m = mat_mul(parent, node_matrix(node))
        if "camera" in node and camera is None:
            cam = g["cameras"][node["camera"]]
            if cam["type"] != "perspective":
                fail("an orthographic camera")
            eye = apply(m, [0, 0, 0], 1)
            look = normalize(apply(m, [0, 0, -1], 0))
            up = normalize(apply(m, [0, 1, 0], 0))
            camera = (eye, [eye[i] + look[i] for i in range(3)], up, cam["perspective"])
        light_ref = node.get("extensions", {}).get("KHR_lights_punctual")
        if light_ref:
            light = lights[light_ref["light"]]
            colour = light.get("color", [1, 1, 1])
            power = " ".join(f"{c * light.get('intensity', 1.0) / LUMENS_PER_WATT:.6g}"
                             for c in colour)
            at = apply(m, [0, 0, 0], 1)
            if light["type"] == "point":
                world.append(f'LightSource "point" "rgb I" [ {power} ] '
                             f'"point3 from" [ {" ".join(f"{c:.6g}" for c in at)} ]')
            elif light["type"] == "directional":
                d = normalize(apply(m, [0, 0, -1], 0))
                world.append(f'LightSource "distant" "rgb L" [ {power} ] "point3 from" [ 0 0 0 ] '
                             f'"point3 to" [ {" ".join(f"{c:.6g}" for c in d)} ]')
            else:
                fail(f"a {light['type']} light")
        if "mesh" in node:
            normal_m = [list(r) for r in zip(*inverse3(m))]  # inverse transpose
            for prim in g["meshes"][node["mesh"]]["primitives"]:
                mesh_lines(model, prim, m, normal_m, world, textures)
        for child in node.get("children", []):
            visit(child, m)

    identity = [[float(i == j) for j in range(4)] for i in range(4)]
    for root in g["scenes"][g.get("scene", 0)]["nodes"]:
        visit(root, identity)
    if camera is None:
        fail("the file has no perspective camera")
    eye, target, up, persp = camera
    aspect = persp.get("aspectRatio", 1.5)
    if aspect < 1:
        fail("a camera taller than wide (pbrt's fov is the shorter side's)")
    height = round(width / aspect)
    f3 = lambda v: " ".join(f"{c:.6g}" for c in v)  # noqa: E731
    lines += ["Scale -1 1 1",
              f"LookAt {f3(eye)}  {f3(target)}  {f3(up)}",
              f'Camera "perspective" "float fov" [ {math.degrees(persp["yfov"]):.6g} ]',
              'PixelFilter "box" "float xradius" [ 0.5 ] "float yradius" [ 0.5 ]',
              f'Film "rgb" "integer xresolution" [ {width} ] "integer yresolution" [ {height} ]',
              f'Sampler "independent" "integer pixelsamples" [ {spp} ]',
              f'Integrator "path" "integer maxdepth" [ {maxdepth} ]',
              "WorldBegin"]
    lines += sorted(set(textures)) + world
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


def mesh_lines(model, prim, m, normal_m, world, textures):
    if prim.get("mode", 4) != 4:
        fail("a primitive that is not triangles")
    attrs = prim["attributes"]
    gm = model.g["materials"][prim["material"]]
    mat_line, light_line = pbrt_material(model, gm)
    if "baseColorTexture" in gm.get("pbrMetallicRoughness", {}):
        info = gm["pbrMetallicRoughness"]["baseColorTexture"]
        scale = gm["pbrMetallicRoughness"].get("baseColorFactor", [1, 1, 1])[0]
        textures.append(f'Texture "{gm.get("name", "?")}-base" "spectrum" "imagemap" '
                        f'"string filename" "{model.image_path(info)}" "float scale" {scale:.6g}')
    transforms = {json.dumps(uv_transform(i)) for i in material_texture_infos(gm)}
    if len(transforms) > 1:
        fail(f"material {gm.get('name')}: textures with different KHR_texture_transforms")
    uvm = json.loads(transforms.pop()) if transforms else None
    p = [apply(m, v, 1) for v in model.accessor(attrs["POSITION"])]
    shape = ['Shape "trianglemesh"',
             '"point3 P" [ ' + " ".join(f"{c:.6g}" for v in p for c in v) + " ]"]
    if "NORMAL" in attrs:
        n = [normalize([sum(normal_m[i][k] * v[k] for k in range(3)) for i in range(3)])
             for v in model.accessor(attrs["NORMAL"])]
        shape.append('"normal N" [ ' + " ".join(f"{c:.6g}" for v in n for c in v) + " ]")
    if "TEXCOORD_0" in attrs:
        uv = model.accessor(attrs["TEXCOORD_0"])
        if uvm:
            uv = [(uvm[0][0] * u + uvm[0][1] * v + uvm[0][2], uvm[1][0] * u + uvm[1][1] * v +
                   uvm[1][2]) for u, v in uv]
        shape.append('"point2 uv" [ ' + " ".join(f"{u:.6g} {1 - v:.6g}" for u, v in uv) + " ]")
    idx = [i[0] for i in model.accessor(prim["indices"])]
    shape.append('"integer indices" [ ' + " ".join(str(i) for i in idx) + " ]")
    world.append("AttributeBegin")
    if light_line:
        world.append("  " + light_line)
    world.append("  " + mat_line)
    world.append("  " + "\n    ".join(shape))
    world.append("AttributeEnd")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("gltf")
    ap.add_argument("pbrt")
    ap.add_argument("--width", type=int, default=240)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--maxdepth", type=int, default=5)
    a = ap.parse_args()
    convert(a.gltf, a.pbrt, a.width, a.spp, a.maxdepth)


main()
