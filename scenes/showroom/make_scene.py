#!/usr/bin/env python3
"""Writes showroom.glb, the glTF 2.0 demo scene: a camera dollying past a textured tile
floor, a chrome sphere, a rough gold sphere and a glass sphere (one sphere mesh shared by
three nodes), a glass sphere rolling across, a red box turning on a moving stand (an
animated child of an animated parent), and an emissive panel as the key light.

Only the standard library is used: the glTF JSON, the binary chunk and the embedded PNG
are assembled here. Run it from anywhere; it writes next to itself."""
import json
import math
import struct
import zlib
from pathlib import Path

HERE = Path(__file__).resolve().parent
FPS = 24
FRAMES = 24  # frames 0..23; the animation lasts 23 / 24 s


class Writer:
    """Collects binary data, buffer views and accessors for one glTF buffer."""

    def __init__(self):
        self.data = bytearray()
        self.gltf = {"asset": {"version": "2.0", "generator": "pathfarm scenes/showroom/make_scene.py"},
                     "bufferViews": [], "accessors": [], "meshes": [], "nodes": [], "materials": [],
                     "images": [], "textures": [], "samplers": [], "cameras": [], "animations": []}

    def view(self, payload):
        while len(self.data) % 4:
            self.data.append(0)
        self.gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(payload)})
        self.data += payload
        return len(self.gltf["bufferViews"]) - 1

    def floats(self, rows, kind, bounds=False):
        flat = [c for row in rows for c in (row if isinstance(row, (list, tuple)) else [row])]
        accessor = {"bufferView": self.view(struct.pack(f"<{len(flat)}f", *flat)), "componentType": 5126,
                    "count": len(rows), "type": kind}
        if bounds:
            width = len(rows[0])
            accessor["min"] = [min(r[i] for r in rows) for i in range(width)]
            accessor["max"] = [max(r[i] for r in rows) for i in range(width)]
        self.gltf["accessors"].append(accessor)
        return len(self.gltf["accessors"]) - 1

    def indices(self, values):
        self.gltf["accessors"].append({"bufferView": self.view(struct.pack(f"<{len(values)}H", *values)),
                                       "componentType": 5123, "count": len(values), "type": "SCALAR"})
        return len(self.gltf["accessors"]) - 1

    def mesh(self, name, positions, normals, uvs, indices, material):
        attributes = {"POSITION": self.floats(positions, "VEC3", True), "NORMAL": self.floats(normals, "VEC3"),
                      "TEXCOORD_0": self.floats(uvs, "VEC2")}
        self.gltf["meshes"].append({"name": name, "primitives": [
            {"attributes": attributes, "indices": self.indices(indices), "material": material}]})
        return len(self.gltf["meshes"]) - 1

    def material(self, name, **fields):
        self.gltf["materials"].append({"name": name, **fields})
        return len(self.gltf["materials"]) - 1

    def node(self, **fields):
        self.gltf["nodes"].append(fields)
        return len(self.gltf["nodes"]) - 1

    def animate(self, name, channels):
        """channels: list of (node, path, times, values, interpolation)."""
        samplers, targets = [], []
        for node, path, times, values, interpolation in channels:
            kind = "VEC4" if path == "rotation" else "VEC3"
            samplers.append({"input": self.floats([[t] for t in times], "SCALAR", True),
                             "output": self.floats(values, kind), "interpolation": interpolation})
            targets.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": path}})
        self.gltf["animations"].append({"name": name, "samplers": samplers, "channels": targets})

    def glb(self):
        while len(self.data) % 4:
            self.data.append(0)
        self.gltf["buffers"] = [{"byteLength": len(self.data)}]
        text = json.dumps({k: v for k, v in self.gltf.items() if v != []}, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        chunks = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(self.data), b"BIN\0") + self.data
        return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def png(width, height, pixel):
    """An 8-bit RGB PNG of pixel(x, y) -> (r, g, b)."""
    rows = b"".join(b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def tiles(x, y, size=256, cells=8):
    """Two-tone tiles with one-texel grout lines: sharp edges that show misregistration."""
    cell = size // cells
    if x % cell == 0 or y % cell == 0:
        return (40, 38, 36)
    return (200, 190, 170) if ((x // cell) + (y // cell)) % 2 == 0 else (120, 95, 70)


def sphere(rings=24, segments=48):
    positions, normals, uvs, indices = [], [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            positions.append(n)
            normals.append(n)
            uvs.append((j / segments, i / rings))
    row = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b = i * row + j, (i + 1) * row + j
            if i > 0:
                indices += [a, b, a + 1]
            if i < rings - 1:
                indices += [a + 1, b, b + 1]
    return positions, normals, uvs, indices


def box():
    positions, normals, uvs, indices = [], [], [], []
    for axis in range(3):
        for sign in (1, -1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [0, 0, 0]
            u[(axis + 1) % 3] = 1
            v = [0, 0, 0]
            v[(axis + 2) % 3] = 1
            base = len(positions)
            for du, dv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                positions.append(tuple(0.5 * (n[k] + du * u[k] + dv * v[k]) for k in range(3)))
                normals.append(tuple(n))
                uvs.append(((du + 1) / 2, (dv + 1) / 2))
            quad = [base, base + 1, base + 2, base, base + 2, base + 3]
            indices += quad if sign > 0 else [quad[0], quad[2], quad[1], quad[3], quad[5], quad[4]]
    return positions, normals, uvs, indices


def quad(half_x, half_z, uv_repeat=1.0):
    """A rectangle in the xz plane facing +y."""
    positions = [(-half_x, 0, half_z), (half_x, 0, half_z), (half_x, 0, -half_z), (-half_x, 0, -half_z)]
    uvs = [(0, uv_repeat), (uv_repeat, uv_repeat), (uv_repeat, 0), (0, 0)]
    return positions, [(0, 1, 0)] * 4, uvs, [0, 1, 2, 0, 2, 3]


def axis_angle(axis, degrees):
    s = math.sin(math.radians(degrees) / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(math.radians(degrees) / 2)]


def look_rotation(eye, target):
    """The quaternion (x, y, z, w) turning -z towards target with +y up."""
    f = [t - e for t, e in zip(target, eye)]
    yaw = math.atan2(-f[0], -f[2])
    pitch = math.atan2(f[1], math.hypot(f[0], f[2]))
    cy, sy, cp, sp = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(pitch / 2), math.sin(pitch / 2)
    return [cy * sp, sy * cp, -sy * sp, cy * cp]  # yaw about y, then pitch about the turned x


def tiles_material(w):
    """The tiled floor: the tiles() texture (image 0, texture 0), rough and not metal."""
    image = w.view(png(256, 256, tiles))
    w.gltf["images"].append({"bufferView": image, "mimeType": "image/png"})
    w.gltf["samplers"].append({"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497})
    w.gltf["textures"].append({"source": 0, "sampler": 0})
    return w.material("tiles", pbrMetallicRoughness={"baseColorTexture": {"index": 0}, "metallicFactor": 0,
                                                      "roughnessFactor": 0.55})


def chrome_material(w):
    return w.material("chrome", pbrMetallicRoughness={"baseColorFactor": [0.95, 0.95, 0.95, 1],
                                                      "metallicFactor": 1, "roughnessFactor": 0.02})


def glass_material(w, thickness):
    """A clear solid: transmission with a volume (the extensions listed by use_extensions)."""
    return w.material("glass", pbrMetallicRoughness={"metallicFactor": 0, "roughnessFactor": 0},
                      extensions={"KHR_materials_transmission": {"transmissionFactor": 1},
                                  "KHR_materials_ior": {"ior": 1.5},
                                  "KHR_materials_volume": {"thicknessFactor": thickness}})


def lamp_material(w):
    """The key light's: warm white emission of strength 14 on a black body."""
    return w.material("lamp", emissiveFactor=[1.0, 0.9, 0.75],
                      pbrMetallicRoughness={"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
                      extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 14}})


def use_extensions(w):
    w.gltf["extensionsUsed"] = ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                                "KHR_materials_emissive_strength"]


def write_scene(w, name, nodes, folder):
    """Makes `nodes` the default scene, named `name`, and writes folder/name.glb."""
    w.gltf["scenes"] = [{"name": name, "nodes": nodes}]
    w.gltf["scene"] = 0
    out = folder / f"{name}.glb"
    out.write_bytes(w.glb())
    print(f"wrote {out} ({out.stat().st_size} bytes)")


def main():
    w = Writer()
    floor = tiles_material(w)
    chrome = chrome_material(w)
    gold = w.material("rough_gold", pbrMetallicRoughness={"baseColorFactor": [1.0, 0.78, 0.34, 1],
                                                          "metallicFactor": 1, "roughnessFactor": 0.35})
    glass = glass_material(w, 0.6)
    red = w.material("red_plastic", pbrMetallicRoughness={"baseColorFactor": [0.75, 0.08, 0.05, 1],
                                                          "metallicFactor": 0, "roughnessFactor": 0.3})
    stand = w.material("stand", pbrMetallicRoughness={"baseColorFactor": [0.3, 0.3, 0.32, 1],
                                                      "metallicFactor": 0, "roughnessFactor": 0.8})
    lamp = lamp_material(w)
    use_extensions(w)

    sphere_mesh = sphere()
    floor_mesh = w.mesh("floor", *quad(6, 6, 6), floor)
    chrome_mesh = w.mesh("chrome_sphere", *sphere_mesh, chrome)
    # One mesh, two nodes: the gold spheres share their triangles.
    gold_mesh = w.mesh("gold_sphere", *sphere_mesh, gold)
    glass_mesh = w.mesh("glass_sphere", *sphere_mesh, glass)
    box_mesh = w.mesh("box", *box(), red)
    stand_mesh = w.mesh("stand", *box(), stand)
    lamp_mesh = w.mesh("lamp", *quad(0.8, 0.5), lamp)

    nodes = [
        w.node(name="floor", mesh=floor_mesh),
        w.node(name="chrome_sphere", mesh=chrome_mesh, translation=[-0.9, 0.45, -0.4], scale=[0.45] * 3),
        w.node(name="gold_sphere", mesh=gold_mesh, translation=[0.6, 0.4, -0.7], scale=[0.4] * 3),
        w.node(name="small_gold_sphere", mesh=gold_mesh, translation=[-1.8, 0.2, 0.4], scale=[0.2] * 3),
        # The key light faces down onto the set.
        w.node(name="key_light", mesh=lamp_mesh, translation=[1.2, 3.2, 1.8],
               rotation=axis_angle((1, 0, 0), 200)),
    ]
    glass_node = w.node(name="glass_sphere", mesh=glass_mesh, translation=[0.2, 0.3, 0.9], scale=[0.3] * 3)
    box_node = w.node(name="turning_box", mesh=box_mesh, translation=[0, 0.35, 0], scale=[0.45] * 3)
    stand_node = w.node(name="stand", mesh=stand_mesh, scale=[0.6, 0.1, 0.6])
    carrier = w.node(name="carrier", children=[box_node, stand_node], translation=[1.6, 0.05, -0.1])
    nodes += [glass_node, carrier]

    end = (FRAMES - 1) / FPS
    eye0, eye1, target = [-1.6, 1.0, 4.2], [0.9, 0.85, 3.4], [0, 0.45, 0]
    camera = w.node(name="dolly_camera", camera=0, translation=eye0, rotation=look_rotation(eye0, target))
    w.gltf["cameras"].append({"name": "dolly", "type": "perspective",
                              "perspective": {"yfov": math.radians(38), "aspectRatio": 16 / 9, "znear": 0.05}})
    nodes.append(camera)

    # The camera eases in and out along the dolly (CUBICSPLINE, zero end tangents) while
    # turning to keep the set in frame.
    mid = [(a + b) / 2 for a, b in zip(eye0, eye1)]
    slope = [(b - a) / end * 1.5 for a, b in zip(eye0, eye1)]
    zero = [0, 0, 0]
    w.animate("shot", [
        (camera, "translation", [0, end / 2, end], [zero, eye0, zero, slope, mid, slope, zero, eye1, zero],
         "CUBICSPLINE"),
        (camera, "rotation", [0, end / 2, end],
         [look_rotation(eye0, target), look_rotation(mid, target), look_rotation(eye1, target)], "LINEAR"),
        (glass_node, "translation", [0, end], [[0.2, 0.3, 0.9], [0.9, 0.3, 0.6]], "LINEAR"),
        (box_node, "rotation", [0, end / 2, end],
         [axis_angle((0, 1, 0), 0), axis_angle((0, 1, 0), 40), axis_angle((0, 1, 0), 80)], "LINEAR"),
        (carrier, "translation", [0, end], [[1.6, 0.05, -0.1], [1.6, 0.05, -0.5]], "LINEAR"),
    ])
    write_scene(w, "showroom", nodes, HERE)


if __name__ == "__main__":
    main()
