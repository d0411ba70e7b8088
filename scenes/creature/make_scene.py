#!/usr/bin/env python3
"""Writes creature.glb, the character scene of the moving-camera suite: a skinned
tentacle swaying on a tiled floor (a chain of five joints, each vertex weighted between
the two nearest, a wave travelling up it), a blob that breathes and stretches (two morph
targets with animated weights, CUBICSPLINE and LINEAR), a chrome sphere that mirrors
both, a glass sphere in front, an emissive key light and a camera dollying past.

The glTF writer is the showroom's (scenes/showroom/make_scene.py). Run it from anywhere;
it writes next to itself."""
import math
import struct
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "showroom"))
from make_scene import (Writer, axis_angle, chrome_material, glass_material, lamp_material, look_rotation,  # noqa: E402
                        quad, sphere, tiles_material, use_extensions, write_scene)

FPS = 24
FRAMES = 24
END = (FRAMES - 1) / FPS
JOINTS = 5
HEIGHT = 1.6


def tentacle(rings=32, segments=24):
    """A tapered tube along +y from 0 to HEIGHT with a rounded tip, and per vertex the two
    joints (of JOINTS spaced evenly up it) it blends between."""
    positions, normals, uvs, indices, joints, weights = [], [], [], [], [], []
    spacing = HEIGHT / (JOINTS - 1)
    for i in range(rings + 1):
        y = HEIGHT * i / rings
        radius = 0.2 - 0.14 * y / HEIGHT
        slope = 0.14 / HEIGHT  # the radius shrinks as y grows: normals tilt up
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            c, s = math.cos(phi), -math.sin(phi)
            positions.append((radius * c, y, radius * s))
            n = (c, slope, s)
            length = math.sqrt(sum(x * x for x in n))
            normals.append(tuple(x / length for x in n))
            uvs.append((j / segments, 1 - i / rings))
            lower = min(int(y / spacing), JOINTS - 2)
            f = min(max(y / spacing - lower, 0.0), 1.0)
            joints.append((lower, lower + 1, 0, 0))
            weights.append((1 - f, f, 0, 0))
    row = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b = i * row + j, (i + 1) * row + j
            indices += [a, a + 1, b, a + 1, b + 1, b]
    # The tip: a fan to one vertex on the last joint.
    tip = len(positions)
    positions.append((0, HEIGHT + 0.04, 0))
    normals.append((0, 1, 0))
    uvs.append((0.5, 0))
    joints.append((JOINTS - 1, 0, 0, 0))
    weights.append((1, 0, 0, 0))
    for j in range(segments):
        a = rings * row + j
        indices += [a, a + 1, tip]
    return positions, normals, uvs, indices, joints, weights


def add_tentacle(w, material):
    positions, normals, uvs, indices, joints, weights = tentacle()
    joint_view = w.view(struct.pack(f"<{4 * len(joints)}H", *[k for row in joints for k in row]))
    w.gltf["accessors"].append({"bufferView": joint_view, "componentType": 5123, "count": len(joints), "type": "VEC4"})
    joint_accessor = len(w.gltf["accessors"]) - 1
    attributes = {"POSITION": w.floats(positions, "VEC3", True), "NORMAL": w.floats(normals, "VEC3"),
                  "TEXCOORD_0": w.floats(uvs, "VEC2"), "JOINTS_0": joint_accessor,
                  "WEIGHTS_0": w.floats(weights, "VEC4")}
    w.gltf["meshes"].append({"name": "tentacle", "primitives": [
        {"attributes": attributes, "indices": w.indices(indices), "material": material}]})
    mesh = len(w.gltf["meshes"]) - 1
    # The joints: a chain up the tentacle, each the previous one's child.
    spacing = HEIGHT / (JOINTS - 1)
    chain = []
    for k in reversed(range(JOINTS)):
        fields = {"name": f"joint{k}", "translation": [0, spacing if k > 0 else 0, 0]}
        if chain:
            fields["children"] = [chain[-1]]
        chain.append(w.node(**fields))
    chain.reverse()  # chain[k] is joint k; joint 0 is the root
    root = w.node(name="tentacle_base", translation=[0.15, 0, -0.2], children=[chain[0]])
    # Inverse bind matrices: joint k sits at y = k * spacing in the mesh's space.
    binds = []
    for k in range(JOINTS):
        binds += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -0.15, -k * spacing, 0.2, 1]
    bind_view = w.view(struct.pack(f"<{len(binds)}f", *binds))
    w.gltf["accessors"].append({"bufferView": bind_view, "componentType": 5126, "count": JOINTS, "type": "MAT4"})
    w.gltf.setdefault("skins", []).append({"name": "tentacle", "joints": chain,
                                           "inverseBindMatrices": len(w.gltf["accessors"]) - 1})
    skinned = w.node(name="tentacle", mesh=mesh, skin=0)
    # A wave up the chain: each joint sways about z and nods about x, a phase behind the
    # one below it.
    times = [END * i / 12 for i in range(13)]
    channels = []
    for k in range(1, JOINTS):
        turns = []
        for t in times:
            phase = 2 * math.pi * t / END - 0.7 * k
            sway, nod = 16 * math.sin(phase), 7 * math.cos(phase)
            turns.append(quaternion_product(axis_angle((0, 0, 1), sway), axis_angle((1, 0, 0), nod)))
        channels.append((chain[k], "rotation", times, turns, "LINEAR"))
    return [root, skinned], channels


def quaternion_product(a, b):
    """a * b for quaternions stored (x, y, z, w)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def add_blob(w, material):
    """A unit sphere with two morph targets: 'breathe' swells it by 25 % along its normals,
    'stretch' makes it 40 % taller (the normals of the stretched ellipsoid as their own
    offsets)."""
    positions, normals, uvs, indices = sphere(20, 40)
    breathe = [tuple(0.25 * c for c in n) for n in normals]
    stretch = [(0, 0.4 * p[1], 0) for p in positions]
    stretch_normals = []
    for n in normals:
        m = (n[0], n[1] / 1.4, n[2])
        length = math.sqrt(sum(c * c for c in m))
        stretch_normals.append(tuple(m[i] / length - n[i] for i in range(3)))
    attributes = {"POSITION": w.floats(positions, "VEC3", True), "NORMAL": w.floats(normals, "VEC3"),
                  "TEXCOORD_0": w.floats(uvs, "VEC2")}
    targets = [{"POSITION": w.floats(breathe, "VEC3", True)},
               {"POSITION": w.floats(stretch, "VEC3", True), "NORMAL": w.floats(stretch_normals, "VEC3")}]
    w.gltf["meshes"].append({"name": "blob", "weights": [0, 0], "primitives": [
        {"attributes": attributes, "indices": w.indices(indices), "material": material, "targets": targets}]})
    node = w.node(name="blob", mesh=len(w.gltf["meshes"]) - 1, translation=[-0.75, 0.32, 0.35], scale=[0.3] * 3)
    # Weights per key: (breathe, stretch). CUBICSPLINE keys hold in-tangent, value, out-tangent.
    zero = [0, 0]
    breath = [zero, [0, 0], zero, zero, [1, 0.5], zero, zero, [0, 1], zero]
    times = [0, END / 2, END]
    samplers = [{"input": w.floats([[t] for t in times], "SCALAR", True),
                 "output": w.floats([[v] for key in breath for v in key], "SCALAR"), "interpolation": "CUBICSPLINE"}]
    return node, samplers


def main():
    w = Writer()
    floor = tiles_material(w)
    skin = w.material("skin", pbrMetallicRoughness={"baseColorFactor": [0.85, 0.3, 0.12, 1], "metallicFactor": 0,
                                                    "roughnessFactor": 0.4})
    jelly = w.material("jelly", pbrMetallicRoughness={"baseColorFactor": [0.2, 0.55, 0.75, 1], "metallicFactor": 0,
                                                      "roughnessFactor": 0.25})
    chrome = chrome_material(w)
    glass = glass_material(w, 0.5)
    lamp = lamp_material(w)
    use_extensions(w)

    sphere_mesh = sphere()
    nodes = [
        w.node(name="floor", mesh=w.mesh("floor", *quad(6, 6, 6), floor)),
        w.node(name="chrome_sphere", mesh=w.mesh("chrome_sphere", *sphere_mesh, chrome),
               translation=[0.95, 0.42, -0.75], scale=[0.42] * 3),
        w.node(name="glass_sphere", mesh=w.mesh("glass_sphere", *sphere_mesh, glass),
               translation=[1.45, 0.22, 0.35], scale=[0.22] * 3),
        w.node(name="key_light", mesh=w.mesh("lamp", *quad(0.8, 0.5), lamp), translation=[1.2, 3.2, 1.8],
               rotation=axis_angle((1, 0, 0), 200)),
    ]
    tentacle_nodes, channels = add_tentacle(w, skin)
    blob, blob_samplers = add_blob(w, jelly)
    nodes += tentacle_nodes + [blob]

    eye0, eye1, target = [-1.5, 1.1, 3.9], [1.1, 0.9, 3.3], [0, 0.6, 0]
    camera = w.node(name="camera", camera=0, translation=eye0, rotation=look_rotation(eye0, target))
    w.gltf["cameras"].append({"name": "dolly", "type": "perspective",
                              "perspective": {"yfov": math.radians(40), "aspectRatio": 16 / 9, "znear": 0.05}})
    nodes.append(camera)
    channels += [(camera, "translation", [0, END], [eye0, eye1], "LINEAR"),
                 (camera, "rotation", [0, END], [look_rotation(eye0, target), look_rotation(eye1, target)], "LINEAR")]
    w.animate("shot", channels)
    # The blob's weights are a channel of the same animation (Writer.animate knows only
    # transforms).
    animation = w.gltf["animations"][0]
    animation["samplers"] += blob_samplers
    animation["channels"].append({"sampler": len(animation["samplers"]) - 1,
                                  "target": {"node": blob, "path": "weights"}})
    write_scene(w, "creature", nodes, HERE)


if __name__ == "__main__":
    main()
