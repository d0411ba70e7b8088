#!/usr/bin/env python3
"""Writes the dolly scene's assets: torus.obj (a torus with normals and uvs) and
tiles.png (a two-tone tile texture with thin grout lines, whose sharp edges show
whether a pipeline registers textures under camera motion)."""
import math
import struct
import zlib
from pathlib import Path

HERE = Path(__file__).resolve().parent


def write_torus(path, major=0.35, minor=0.13, rings=48, sides=24):
    lines = ["# torus written by make_assets.py"]
    for i in range(rings + 1):
        u = 2 * math.pi * i / rings
        for j in range(sides + 1):
            v = 2 * math.pi * j / sides
            nx, ny, nz = math.cos(u) * math.cos(v), math.sin(v), math.sin(u) * math.cos(v)
            x = math.cos(u) * (major + minor * math.cos(v))
            z = math.sin(u) * (major + minor * math.cos(v))
            y = minor * math.sin(v)
            lines.append(f"v {x:.6f} {y:.6f} {z:.6f}")
            lines.append(f"vn {nx:.6f} {ny:.6f} {nz:.6f}")
            lines.append(f"vt {i / rings:.6f} {j / sides:.6f}")
    row = sides + 1
    for i in range(rings):
        for j in range(sides):
            a, b = i * row + j + 1, (i + 1) * row + j + 1
            c, d = b + 1, a + 1
            lines.append(f"f {a}/{a}/{a} {d}/{d}/{d} {c}/{c}/{c} {b}/{b}/{b}")
    path.write_text("\n".join(lines) + "\n")


def write_png(path, width, height, pixel):
    raw = bytearray()
    for y in range(height):
        raw.append(0)
        for x in range(width):
            raw.extend(pixel(x, y))

    def chunk(tag, data):
        body = tag + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(raw), 9)) +
                     chunk(b"IEND", b""))


def tile(x, y, size=384, tiles=24):
    cell = size // tiles
    if x % cell < 1 or y % cell < 1:
        return (40, 40, 40)  # grout
    return (200, 190, 170) if (x // cell + y // cell) % 2 == 0 else (120, 60, 45)


if __name__ == "__main__":
    write_torus(HERE / "torus.obj")
    write_png(HERE / "tiles.png", 384, 384, tile)
