#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Writes the seed corpus of fuzz_mesh_import into mesh/ beside this script: one small
# tetrahedron (mm) in every format loadMesh reads through assimp: STL ASCII
# and binary, OBJ (with a quad, a group and a comment), glTF with an
# embedded buffer, and GLB. Deterministic: the committed files are its output.
import base64
import json
import os
import struct

here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "mesh")
V = [(0.0, 0.0, 0.0), (30.0, 0.0, 0.0), (0.0, 30.0, 0.0), (0.0, 0.0, 30.0)]
F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def normal(f):
    a, b, c = (V[i] for i in f)
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    length = sum(x * x for x in n) ** 0.5
    return [x / length for x in n]


def write(name, data):
    with open(os.path.join(here, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


stl = "solid tetra\n"
for f in F:
    stl += "facet normal %g %g %g\n outer loop\n" % tuple(normal(f))
    for i in f:
        stl += "  vertex %g %g %g\n" % V[i]
    stl += " endloop\nendfacet\n"
write("tetra_ascii.stl", stl + "endsolid tetra\n")

b = b"binary tetra".ljust(80, b"\0") + struct.pack("<I", len(F))
for f in F:
    b += struct.pack("<3f", *normal(f))
    for i in f:
        b += struct.pack("<3f", *V[i])
    b += b"\0\0"
write("tetra_binary.stl", b)

obj = "# tetrahedron and a square\no tetra\ng sides\n"
obj += "".join("v %g %g %g\n" % v for v in V)
obj += "v 50 0 0\nv 60 0 0\nv 60 10 0\nv 50 10 0\nvn 0 0 1\n"
obj += "".join("f %d %d %d\n" % tuple(i + 1 for i in f) for f in F)
obj += "f 5//1 6//1 7//1 8//1\n"
write("tetra.obj", obj)

buf = b"".join(struct.pack("<3f", *v) for v in V) + b"".join(struct.pack("<3I", *f) for f in F)


def gltf(buffer):
    return {
        "asset": {"version": "2.0"},
        "buffers": [buffer],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48, "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [30, 30, 30]},
            {"bufferView": 1, "componentType": 5125, "count": 12, "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],
        "nodes": [{"children": [1], "translation": [5, 0, 0]}, {"mesh": 0, "scale": [1, 1, 1]}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }


uri = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
write("tetra.gltf", json.dumps(gltf({"byteLength": len(buf), "uri": uri}), separators=(",", ":")))

js = json.dumps(gltf({"byteLength": len(buf)}), separators=(",", ":")).encode()
js += b" " * (-len(js) % 4)
glb = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(buf))
glb += struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(buf), 0x004E4942) + buf
write("tetra.glb", glb)
