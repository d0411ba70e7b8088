#!/usr/bin/env python3
"""Writes the glTF files of the scale benchmark (bench/gltf_scale.sh) into a folder:

  terrain.glb    one mesh of 1,002,528 triangles (a 708 x 708 grid of quads, displaced
                 into rolling hills, with normals and uvs) under a camera
  rocks_N.glb    one bumpy sphere mesh of 100,352 triangles placed by N nodes in a grid
                 (N = 1, 10, 100), each turned and scaled its own way
  rocks_100_copies.glb  the same 100 placements, each node with a mesh of its own (100
                 glTF meshes reading the same accessors), which the importer loads as
                 100 meshes: the baseline that instancing is measured against
  character.glb  a skinned tube of 100,000 triangles bending on a chain of 60 joints, each
                 vertex weighted to the 4 joints nearest along it, every joint turning on
                 its own keys (24 a second): what posing a character per frame costs

and beside each a JSON scene that includes it under a constant sky. Standard library
only; the binary chunk is written with array, so a million triangles take a few seconds.

  make_scale_scenes.py OUT_DIR"""
import array
import json
import math
import struct
import sys
from pathlib import Path


def glb(document, payload):
    """A GLB container: the JSON chunk, then the binary chunk, each padded to 4 bytes."""
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    payload += b"\0" * (-len(payload) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(payload), 0x004E4942) + payload
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def mesh_document(positions, normals, uvs, indices):
    """glTF JSON and binary data for one mesh (float32 attributes, uint32 indices)."""
    parts, views, accessors = [], [], []
    offset = 0
    vertex_count = len(positions) // 3
    for values, kind, count, component in ((positions, "VEC3", vertex_count, 5126), (normals, "VEC3", vertex_count, 5126),
                                           (uvs, "VEC2", vertex_count, 5126), (indices, "SCALAR", len(indices), 5125)):
        data = values.tobytes()
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(data)})
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": kind}
        if kind == "VEC3" and not accessors:
            accessor["min"] = [min(values[i::3]) for i in range(3)]
            accessor["max"] = [max(values[i::3]) for i in range(3)]
        accessors.append(accessor)
        parts.append(data)
        offset += len(data)
    document = {"asset": {"version": "2.0", "generator": "pathfarm bench/gltf_scale/make_scale_scenes.py"},
                "buffers": [{"byteLength": offset}], "bufferViews": views, "accessors": accessors,
                "materials": [{"name": "stone", "pbrMetallicRoughness": {
                    "baseColorFactor": [0.55, 0.5, 0.45, 1], "metallicFactor": 0, "roughnessFactor": 0.7}}],
                "meshes": [{"name": "mesh", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                                            "indices": 3, "material": 0}]}]}
    return document, b"".join(parts)


def grid_indices(columns, rows):
    """Two triangles per quad of a (columns + 1) x (rows + 1) vertex grid, counter-clockwise
    seen from the side the normals point to."""
    indices = array.array("I")
    for j in range(rows):
        for i in range(columns):
            a = j * (columns + 1) + i
            b, c, d = a + 1, a + columns + 1, a + columns + 2
            indices.extend((a, c, b, b, c, d))
    return indices


def terrain(n=708, size=20.0):
    """Hills over [-size/2, size/2]^2 in xz, y up: height h(x, z) with its analytic normal."""
    positions, normals, uvs = array.array("f"), array.array("f"), array.array("f")
    for j in range(n + 1):
        z = size * (j / n - 0.5)
        for i in range(n + 1):
            x = size * (i / n - 0.5)
            h = 0.6 * math.sin(0.7 * x) * math.cos(0.5 * z) + 0.15 * math.sin(3.1 * x + 2.3 * z)
            dhdx = 0.42 * math.cos(0.7 * x) * math.cos(0.5 * z) + 0.465 * math.cos(3.1 * x + 2.3 * z)
            dhdz = -0.3 * math.sin(0.7 * x) * math.sin(0.5 * z) + 0.345 * math.cos(3.1 * x + 2.3 * z)
            length = math.sqrt(dhdx * dhdx + 1 + dhdz * dhdz)
            positions.extend((x, h, z))
            normals.extend((-dhdx / length, 1 / length, -dhdz / length))
            uvs.extend((i / n, j / n))
    return positions, normals, uvs, grid_indices(n, n)


def bumpy_sphere(segments=224, rows=224):
    """A unit sphere with bumps of 5 %, as a latitude-longitude grid (poles included as
    rows of coincident vertices, whose degenerate triangles the importer drops)."""
    positions, normals, uvs = array.array("f"), array.array("f"), array.array("f")
    for j in range(rows + 1):
        theta = math.pi * j / rows
        for i in range(segments + 1):
            phi = 2 * math.pi * i / segments
            d = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            r = 1 + 0.05 * math.sin(7 * phi) * math.sin(5 * theta)
            positions.extend((r * d[0], r * d[1], r * d[2]))
            normals.extend(d)  # the sphere's: shading smooths the bumps, as a low-poly proxy would
            uvs.extend((i / segments, j / rows))
    # Seen from outside, the grid runs clockwise: flip each triangle.
    indices = grid_indices(segments, rows)
    for t in range(0, len(indices), 3):
        indices[t + 1], indices[t + 2] = indices[t + 2], indices[t + 1]
    return positions, normals, uvs, indices


def skinned_tube(rings=500, segments=100, joints=60, height=3.0):
    """A tube along y of radius 0.25 (2 x rings x segments triangles) and, per vertex, the 4
    joints nearest along y (joint k at y = k * height / (joints - 1)) with hat weights."""
    positions, normals, uvs = array.array("f"), array.array("f"), array.array("f")
    vertex_joints, vertex_weights = array.array("H"), array.array("f")
    spacing = height / (joints - 1)
    for j in range(rings + 1):
        y = height * j / rings
        nearest = min(max(int(round(y / spacing)) - 1, 0), joints - 4)
        hats = [max(0.0, 1.5 - abs(y / spacing - (nearest + k))) for k in range(4)]
        total = sum(hats)
        for i in range(segments + 1):
            phi = 2 * math.pi * i / segments
            positions.extend((0.25 * math.cos(phi), y, -0.25 * math.sin(phi)))
            normals.extend((math.cos(phi), 0, -math.sin(phi)))
            uvs.extend((i / segments, j / rings))
            vertex_joints.extend(nearest + k for k in range(4))
            vertex_weights.extend(h / total for h in hats)
    return positions, normals, uvs, grid_indices(segments, rings), vertex_joints, vertex_weights


def add_skin(document, payload, vertex_joints, vertex_weights, joints=60, height=3.0, keys=24):
    """The tube's skin: JOINTS_0/WEIGHTS_0, a chain of joint nodes, their inverse bind
    matrices and a second of animation turning each joint on its own phase."""
    spacing = height / (joints - 1)
    times = array.array("f", (k / keys for k in range(keys + 1)))
    binds = array.array("f")
    for k in range(joints):
        binds.extend((1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -k * spacing, 0, 1))
    turns = []
    for k in range(joints):
        rotation = array.array("f")
        for t in times:
            angle = 0.06 * math.sin(2 * math.pi * t + 0.3 * k)
            rotation.extend((0, 0, math.sin(angle / 2), math.cos(angle / 2)))
        turns.append(rotation)
    blocks = [(vertex_joints, "VEC4", 5123), (vertex_weights, "VEC4", 5126), (binds, "MAT4", 5126),
              (times, "SCALAR", 5126)] + [(r, "VEC4", 5126) for r in turns]
    widths = {"SCALAR": 1, "VEC4": 4, "MAT4": 16}
    first = len(document["accessors"])
    for values, kind, component in blocks:
        data = values.tobytes()
        payload += b"\0" * (-len(payload) % 4)
        document["bufferViews"].append({"buffer": 0, "byteOffset": len(payload), "byteLength": len(data)})
        accessor = {"bufferView": len(document["bufferViews"]) - 1, "componentType": component,
                    "count": len(values) // widths[kind], "type": kind}
        if kind == "SCALAR":
            accessor["min"], accessor["max"] = [min(values)], [max(values)]
        document["accessors"].append(accessor)
        payload += data
    document["buffers"][0]["byteLength"] = len(payload)
    attributes = document["meshes"][0]["primitives"][0]["attributes"]
    attributes["JOINTS_0"], attributes["WEIGHTS_0"] = first, first + 1
    nodes = document["nodes"]
    chain = []
    for k in range(joints):
        chain.append(len(nodes))
        nodes.append({"name": f"joint{k}", "translation": [0, spacing if k else 0, 0]})
        if k:
            nodes[chain[k - 1]]["children"] = [chain[k]]
    document["skins"] = [{"joints": chain, "inverseBindMatrices": first + 2}]
    nodes.append({"name": "character", "mesh": 0, "skin": 0})
    document["animations"] = [{"samplers": [{"input": first + 3, "output": first + 4 + k} for k in range(joints)],
                               "channels": [{"sampler": k, "target": {"node": chain[k], "path": "rotation"}}
                                            for k in range(joints)]}]
    return payload, [chain[0], len(nodes) - 1]


def camera_node(document, position, target):
    """A perspective camera at `position` looking at `target` (y up)."""
    forward = [t - p for t, p in zip(target, position)]
    norm = math.sqrt(sum(f * f for f in forward))
    fx, fy, fz = (f / norm for f in forward)
    # The rotation taking -z to `forward` with no roll: yaw about y, then pitch about x.
    yaw = math.atan2(-fx, -fz)
    pitch = math.asin(fy)
    qy = (0, math.sin(yaw / 2), 0, math.cos(yaw / 2))
    qx = (math.sin(pitch / 2), 0, 0, math.cos(pitch / 2))
    q = (qy[3] * qx[0] + qy[0] * qx[3] + qy[1] * qx[2] - qy[2] * qx[1],
         qy[3] * qx[1] - qy[0] * qx[2] + qy[1] * qx[3] + qy[2] * qx[0],
         qy[3] * qx[2] + qy[0] * qx[1] - qy[1] * qx[0] + qy[2] * qx[3],
         qy[3] * qx[3] - qy[0] * qx[0] - qy[1] * qx[1] - qy[2] * qx[2])
    document["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.01, "aspectRatio": 16 / 9}}]
    document["nodes"].append({"name": "camera", "camera": 0, "translation": list(position), "rotation": list(q)})
    return len(document["nodes"]) - 1


def write(out, name, document, payload, shutter=None):
    """The .glb and a JSON scene including it (with the motion-blur shutter, if given)."""
    (out / f"{name}.glb").write_bytes(glb(document, payload))
    include = {"file": f"{name}.glb", "shutter": shutter} if shutter else f"{name}.glb"
    scene = {"include": include, "environment": {"radiance": [0.9, 0.95, 1.0]},
             "render": {"resolution": [320, 180], "spp": 4, "max_depth": 4}}
    (out / f"{name}.json").write_text(json.dumps(scene, indent=1) + "\n")


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    out.mkdir(parents=True, exist_ok=True)

    document, payload = mesh_document(*terrain())
    document["nodes"] = [{"name": "terrain", "mesh": 0}]
    document["scenes"] = [{"nodes": [0, camera_node(document, (0, 4, 11), (0, 0, 0))]}]
    document["scene"] = 0
    write(out, "terrain", document, payload)

    positions, normals, uvs, indices, vertex_joints, vertex_weights = skinned_tube()
    document, payload = mesh_document(positions, normals, uvs, indices)
    document["nodes"] = []
    payload, roots = add_skin(document, payload, vertex_joints, vertex_weights)
    document["scenes"] = [{"nodes": roots + [camera_node(document, (0, 1.5, 6), (0, 1.5, 0))]}]
    document["scene"] = 0
    write(out, "character", document, payload, shutter=[0, 0.5])

    sphere = bumpy_sphere()
    for count, copies in ((1, False), (10, False), (100, False), (100, True)):
        document, payload = mesh_document(*sphere)
        if copies:
            document["meshes"] = [document["meshes"][0]] * count
        document["nodes"] = []
        side = math.ceil(math.sqrt(count))
        for k in range(count):
            i, j = k % side, k // side
            angle = 0.7 * k
            scale = 0.35 + 0.1 * ((k * 37) % 5) / 4
            document["nodes"].append({"name": f"rock{k}", "mesh": k if copies else 0,
                                      "translation": [(i - (side - 1) / 2) * 1.1, scale, (j - (side - 1) / 2) * 1.1],
                                      "rotation": [0, math.sin(angle / 2), 0, math.cos(angle / 2)],
                                      "scale": [scale, scale * 0.8, scale]})
        roots = list(range(count))
        roots.append(camera_node(document, (0, 0.6 * side + 1.5, 0.9 * side + 2.5), (0, 0, 0)))
        document["scenes"] = [{"nodes": roots}]
        document["scene"] = 0
        write(out, f"rocks_{count}" + ("_copies" if copies else ""), document, payload)


if __name__ == "__main__":
    main()
