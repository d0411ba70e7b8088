#!/usr/bin/env python3
"""Writes sky.hdr, the demo scene's environment map: a 256x128 equirectangular sky
(docs/scene-format.md's orientation: top row +y, image centre +x) with a blue zenith, a
pale horizon, a brown ground and a small sun 35 degrees up, a quarter turn from +x
towards -z. Flat (uncompressed) Radiance RGBE, which every .hdr reader accepts.

    python3 scenes/sky/make_sky.py   # rewrites scenes/sky/sky.hdr
"""
import math
import pathlib

WIDTH, HEIGHT = 256, 128
SUN_ELEVATION, SUN_AZIMUTH = math.radians(35), math.radians(-90)  # azimuth from +x towards +z
SUN_COS_RADIUS = math.cos(math.radians(2.5))
SUN = (math.cos(SUN_ELEVATION) * math.cos(SUN_AZIMUTH), math.sin(SUN_ELEVATION),
       math.cos(SUN_ELEVATION) * math.sin(SUN_AZIMUTH))


def radiance(d):
    if sum(a * b for a, b in zip(d, SUN)) > SUN_COS_RADIUS:
        return (400.0, 360.0, 300.0)
    if d[1] < 0:
        return (0.18, 0.14, 0.1)
    t = d[1] ** 0.5  # horizon (t = 0) to zenith (t = 1)
    return (0.9 - 0.7 * t, 0.95 - 0.55 * t, 1.0 - 0.1 * t)


def rgbe(rgb):
    m = max(rgb)
    if m < 1e-32:
        return bytes(4)
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes([int(c * scale) for c in rgb] + [exponent + 128])


def main():
    pixels = bytearray()
    for y in range(HEIGHT):
        theta = math.pi * (y + 0.5) / HEIGHT
        for x in range(WIDTH):
            phi = 2 * math.pi * ((x + 0.5) / WIDTH - 0.5)
            d = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            pixels += rgbe(radiance(d))
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {HEIGHT} +X {WIDTH}\n".encode()
    out = pathlib.Path(__file__).with_name("sky.hdr")
    out.write_bytes(header + bytes(pixels))


if __name__ == "__main__":
    main()
