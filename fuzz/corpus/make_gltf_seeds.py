#!/usr/bin/env python3
"""Writes the glTF fuzzer's seed corpus (fuzz/corpus/gltf_loader/): small valid files that
reach every part of the importer — a textured .glb, an animated hierarchy with every
sampler kind, a character (a skinned, morphing quad with animated joints and weights)
and a .gltf with its buffer in a data URI."""
import base64
import json
import struct
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent.parent / "scenes" / "showroom"))
from make_scene import Writer, axis_angle, box, png, quad  # noqa: E402


def textured_glb():
    w = Writer()
    w.gltf["images"].append({"bufferView": w.view(png(4, 4, lambda x, y: (x * 60, y * 60, 90))), "mimeType": "image/png"})
    w.gltf["textures"].append({"source": 0})
    m = w.material("m", pbrMetallicRoughness={"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 0}},
                   emissiveFactor=[0.5, 0.5, 0.5])
    mesh = w.mesh("floor", *quad(1, 1, 2), m)
    w.gltf["cameras"].append({"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1, "aspectRatio": 1.5}})
    w.gltf["scenes"] = [{"nodes": [w.node(mesh=mesh), w.node(camera=0, translation=[0, 1, 3])]}]
    return w.glb()


def animated_glb():
    w = Writer()
    m = w.material("glass", extensions={"KHR_materials_transmission": {"transmissionFactor": 1},
                                        "KHR_materials_ior": {"ior": 1.4}})
    mesh = w.mesh("box", *box(), m)
    child = w.node(mesh=mesh, translation=[0, 1, 0], scale=[0.5, 0.5, 0.5])
    parent = w.node(children=[child], matrix=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -2, 1])
    w.animate("all", [
        (child, "rotation", [0, 1], [axis_angle((0, 1, 0), 0), axis_angle((0, 1, 0), 90)], "LINEAR"),
        (child, "scale", [0, 0.5], [[0.5] * 3, [0.7] * 3], "STEP"),
        (parent, "translation", [0, 1], [[0] * 3, [0] * 3, [1, 0, 0], [0] * 3, [1, 0, 0], [0] * 3], "CUBICSPLINE"),
    ])
    w.gltf["scenes"] = [{"nodes": [parent]}]
    return w.glb()


def character_glb():
    w = Writer()
    positions, normals, uvs, indices = quad(1, 1)
    joints = w.view(struct.pack("<16H", 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0))
    w.gltf["accessors"].append({"bufferView": joints, "componentType": 5123, "count": 4, "type": "VEC4"})
    joint_accessor = len(w.gltf["accessors"]) - 1
    attributes = {"POSITION": w.floats(positions, "VEC3", True), "NORMAL": w.floats(normals, "VEC3"),
                  "TEXCOORD_0": w.floats(uvs, "VEC2"), "JOINTS_0": joint_accessor,
                  "WEIGHTS_0": w.floats([(1, 0, 0, 0), (1, 0, 0, 0), (1, 0, 0, 0), (0.5, 0.5, 0, 0)], "VEC4")}
    rise = w.floats([(0, 0.5, 0)] * 4, "VEC3", True)
    w.gltf["meshes"].append({"primitives": [{"attributes": attributes, "indices": w.indices(indices),
                                             "targets": [{"POSITION": rise}]}], "weights": [0.25]})
    tip = w.node(translation=[1, 0, 0])
    root = w.node(children=[tip])
    binds = w.view(struct.pack("<32f", *([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] +
                                         [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1])))
    w.gltf["accessors"].append({"bufferView": binds, "componentType": 5126, "count": 2, "type": "MAT4"})
    w.gltf["skins"] = [{"joints": [root, tip], "inverseBindMatrices": len(w.gltf["accessors"]) - 1}]
    skinned = w.node(mesh=0, skin=0)
    w.animate("wave", [(tip, "rotation", [0, 1], [axis_angle((0, 0, 1), 0), axis_angle((0, 0, 1), 60)], "LINEAR")])
    animation = w.gltf["animations"][0]
    animation["samplers"].append({"input": w.floats([[0], [0.5]], "SCALAR", True),
                                  "output": w.floats([[0], [1]], "SCALAR"), "interpolation": "STEP"})
    animation["channels"].append({"sampler": 1, "target": {"node": skinned, "path": "weights"}})
    w.gltf["scenes"] = [{"nodes": [root, skinned]}]
    return w.glb()


def data_uri_gltf():
    w = Writer()
    mesh = w.mesh("quad", *quad(1, 1), w.material("plain"))
    w.gltf["scenes"] = [{"nodes": [w.node(mesh=mesh)]}]
    w.gltf["buffers"] = [{"byteLength": len(w.data),
                          "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(w.data)).decode()}]
    return json.dumps({k: v for k, v in w.gltf.items() if v != []}).encode()


def main():
    out = HERE / "gltf_loader"
    out.mkdir(exist_ok=True)
    for name, data in (("textured.glb", textured_glb()), ("animated.glb", animated_glb()),
                       ("character.glb", character_glb()), ("data_uri.gltf", data_uri_gltf())):
        (out / name).write_bytes(data)
        print(f"wrote {out / name} ({len(data)} bytes)")


if __name__ == "__main__":
    main()
