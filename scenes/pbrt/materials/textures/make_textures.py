#!/usr/bin/env python3
"""Writes the small tileable textures of ../bump_maps.pbrt (pure Python, no numpy):
height.png   16-bit grey height field (bump map), 64 x 64, two bumps a period each way;
roughness.png 16-bit grey roughness stripes along u, 64 x 64;
normal.png   8-bit RGB tangent-space normal map of a ripple along u, 64 x 64;
leaves.png   8-bit RGBA leaves for ../alpha_masks.pbrt: green to yellow leaves (alpha 1) on
             nothing (alpha 0), 64 x 64.
Run from this folder: python3 make_textures.py"""
import math
import struct
import zlib

N = 64


def png(path, rows, bits, channels):
    """rows: a list of lists of ints (channels interleaved), bits 8 or 16 (also used by
    ../../../gltf/make_showcase.py)."""
    colour = {1: 0, 3: 2, 4: 6}[channels]
    raw = b""
    for row in rows:
        raw += b"\x00" + b"".join(struct.pack(">H" if bits == 16 else "B", v) for v in row)
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    head = struct.pack(">IIBBBBB", len(rows[0]) // channels, len(rows), bits, colour, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def grey16(v):
    return max(0, min(65535, round(v * 65535)))


# Texel (i, j) (j = row from the top) sits at u = (i + 0.5) / N, v = 1 - (j + 0.5) / N.
def uv(i, j):
    return (i + 0.5) / N, 1.0 - (j + 0.5) / N


def main():
    height = []
    rough = []
    normal = []
    for j in range(N):
        hrow, rrow, nrow = [], [], []
        for i in range(N):
            u, v = uv(i, j)
            hrow.append(grey16(0.5 + 0.5 * math.sin(4 * math.pi * u) * math.sin(4 * math.pi * v)))
            rrow.append(grey16(0.02 + 0.4 * (0.5 + 0.5 * math.sin(6 * math.pi * u))))
            # A ripple h = 0.04 sin(2 pi 3 u): the normal (-dh/du, 0, 1) normalised.
            s = -0.04 * 6 * math.pi * math.cos(6 * math.pi * u)
            n = (s, 0.0, 1.0)
            ln = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
            nrow += [max(0, min(255, round((c / ln * 0.5 + 0.5) * 255))) for c in n]
        height.append(hrow)
        rough.append(rrow)
        normal.append(nrow)
    png("height.png", height, 16, 1)
    png("roughness.png", rough, 16, 1)
    png("normal.png", normal, 8, 3)


    # Leaves: four ellipses at angles, each tapering to a tip, a vein darker along the middle.
    LEAVES = [(0.28, 0.30, 0.5), (0.70, 0.28, -0.6), (0.30, 0.74, -0.3), (0.72, 0.70, 0.9)]
    leaves = []
    for j in range(N):
        row = []
        for i in range(N):
            u, v = uv(i, j)
            texel = [0, 0, 0, 0]
            for k, (cu, cv, angle) in enumerate(LEAVES):
                du, dv = u - cu, v - cv
                a = du * math.cos(angle) + dv * math.sin(angle)  # along the leaf
                b = -du * math.sin(angle) + dv * math.cos(angle)
                half_width = 0.09 * (1.0 - (a / 0.2) ** 2) if abs(a) < 0.2 else -1.0
                if abs(b) < half_width:
                    shade = 0.6 + 0.4 * (1.0 - abs(b) / half_width)
                    g = 0.35 + 0.12 * k
                    texel = [round(255 * shade * (0.15 + 0.2 * k)), round(255 * shade * g),
                             round(255 * shade * 0.08), 255]
            row += texel
        leaves.append(row)
    png("leaves.png", leaves, 8, 4)


if __name__ == "__main__":
    main()
