#!/usr/bin/env python3
"""Writes the binary files of the fuzz targets' inputs: in fuzz/assets the texture, sky and
glTF file that the scene seeds name, and in fuzz/corpus/mesh_readers the binary PLY seeds
(both byte orders, every scalar type, list counts of every width). The text seeds (JSON
scenes and shots, OBJ and ascii PLY files) are written by hand; the EXR chunks by
make_exr_seeds.cpp, the glTF files by make_gltf_seeds.py."""
import struct
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ASSETS = HERE.parent / "assets"
sys.path.insert(0, str(HERE.parent.parent / "scenes" / "showroom"))
from make_scene import Writer, box, png  # noqa: E402


def hdr(width, height, pixel):
    """A Radiance .hdr of pixel(x, y) -> (r, g, b), flat RGBE scanlines."""
    def rgbe(r, g, b):
        top = max(r, g, b)
        if top < 1e-32:
            return bytes(4)
        exponent = 0
        while top >= 1:
            top /= 2
            exponent += 1
        while top < 0.5:
            top *= 2
            exponent -= 1
        scale = 256 / 2 ** exponent
        return bytes([int(r * scale), int(g * scale), int(b * scale), exponent + 128])

    head = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode()
    return head + b"".join(rgbe(*pixel(x, y)) for y in range(height) for x in range(width))


def box_glb():
    w = Writer()
    mesh = w.mesh("box", *box(), w.material("paint", pbrMetallicRoughness={"baseColorFactor": [0.8, 0.2, 0.2, 1]}))
    w.gltf["cameras"].append({"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}})
    w.gltf["scenes"] = [{"name": "Scene", "nodes": [w.node(name="box", mesh=mesh), w.node(name="cam", camera=0, translation=[0, 1, 4])]}]
    return w.glb()


SCALARS = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f", "double": "d"}


def binary_ply(order, position_type, index_type, count_type, extra):
    """A quad as two triangles plus a stray vertex, with normals, uvs and an ignored property."""
    mark = "<" if order == "binary_little_endian" else ">"
    vertices = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
    head = (f"ply\nformat {order} 1.0\ncomment pathfarm fuzz seed\n"
            f"element vertex {len(vertices)}\n" +
            "".join(f"property {position_type} {name}\n" for name in ("x", "y", "z")) +
            f"property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
            f"property {extra} quality\n"
            f"element face 3\nproperty list {count_type} {index_type} vertex_indices\nend_header\n").encode()
    body = b""
    for x, y, z in vertices:
        body += struct.pack(mark + SCALARS[position_type] * 3, *(v if position_type in ("float", "double") else
                                                                  int(v) for v in (x, y, z)))
        body += struct.pack(mark + "5f", 0, 0, 1, x, y)
        body += struct.pack(mark + SCALARS[extra], 7)
    for face in ((0, 1, 2), (0, 2, 3), (0, 1, 2, 3, 4)):
        body += struct.pack(mark + SCALARS[count_type], len(face))
        body += struct.pack(mark + SCALARS[index_type] * len(face), *face)
    return head + body


def main():
    ASSETS.mkdir(exist_ok=True)
    meshes = HERE / "mesh_readers"
    meshes.mkdir(exist_ok=True)
    files = {
        ASSETS / "texture.png": png(4, 4, lambda x, y: (x * 60, y * 60, 90)),
        ASSETS / "sky.hdr": hdr(8, 4, lambda x, y: (0.2 + x / 8, 0.3, 1.0 - y / 4)),
        ASSETS / "box.glb": box_glb(),
        meshes / "little.ply": binary_ply("binary_little_endian", "float", "int", "uchar", "uchar"),
        meshes / "big.ply": binary_ply("binary_big_endian", "double", "uint", "ushort", "short"),
        meshes / "narrow.ply": binary_ply("binary_little_endian", "short", "ushort", "int", "double"),
        meshes / "bytes.ply": binary_ply("binary_big_endian", "char", "uchar", "uint", "char"),
    }
    for path, data in files.items():
        path.write_bytes(data)
        print(f"wrote {path} ({len(data)} bytes)")


if __name__ == "__main__":
    main()
