"""Writes the glTF test files of crates/import/tests/gltf.rs with writers that are not
Irradia's: trimesh (the textured box, as GLB) and pygltflib (everything else).

    pip install trimesh pygltflib pillow numpy
    python3 make.py        # in this folder; rewrites the files below

- textured_box.glb: a unit cube with uv and an embedded 8x8 PNG checker texture
  (trimesh's exporter: baseColorTexture in a buffer view).
- hierarchy.gltf (buffers as data URIs): a parent node (TRS: rotation about y by 90
  degrees, translation (2, 0, 0)) whose child (a matrix: scale 0.5, translation
  (0, 1, 0)) holds a quad; the quad's mesh has two primitives, the second without
  indices and with COLOR_0 vertex colours; a metallic-roughness material with factors.
- camera_lights.gltf + camera_lights.bin (an external buffer): a ground quad, a
  perspective camera at (0, 1, 5) looking down -z (aspect 1.5), and
  KHR_lights_punctual point (100 cd), spot (50 cd, cones 10 and 30 degrees) and
  directional (3 lux, pointing down) lights.
- ortho.gltf: one triangle seen by an orthographic camera (ymag 2).
- extensions.gltf + checker.png: a quad with uv whose material uses
  KHR_texture_transform on its base colour texture (offset (0.5, 0.25), rotation 0.3,
  scale (2, 3)) with baseColorFactor (0.5, 1, 1), an emissive texture with
  emissiveFactor (1, 0.5, 0.25) and KHR_materials_emissive_strength 4,
  KHR_materials_transmission 0.8 and KHR_materials_ior 1.33.
"""

import base64
import io
import math
import struct

import numpy as np
import pygltflib as g
import trimesh
from PIL import Image


def textured_box():
    # 24 vertices: each face has its own uv square.
    faces = [
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
        ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
        ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
        ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ]
    v, uv, f = [], [], []
    for n, u, w in faces:
        n, u, w = map(np.array, (n, u, w))
        base = len(v)
        for (a, b) in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
            v.append(0.5 * (n + a * u + b * w))
            uv.append(((a + 1) / 2, (b + 1) / 2))
        f += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
    img = Image.new("RGB", (8, 8))
    for y in range(8):
        for x in range(8):
            img.putpixel((x, y), (230, 40, 30) if (x + y) % 2 else (240, 240, 240))
    mesh = trimesh.Trimesh(
        vertices=np.array(v),
        faces=np.array(f),
        visual=trimesh.visual.TextureVisuals(uv=np.array(uv), image=img),
        process=False,
    )
    mesh.export("textured_box.glb")


def pack(arrays):
    """Concatenates arrays (4-byte aligned); returns bytes and (offset, length) each."""
    blob, spans = b"", []
    for a in arrays:
        data = a.tobytes()
        while len(blob) % 4:
            blob += b"\0"
        spans.append((len(blob), len(data)))
        blob += data
    return blob, spans


def accessors(gl, spans, arrays, kinds, targets):
    for (off, ln), a, kind, target in zip(spans, arrays, kinds, targets):
        gl.bufferViews.append(g.BufferView(buffer=0, byteOffset=off, byteLength=ln, target=target))
        ctype = g.UNSIGNED_INT if a.dtype == np.uint32 else g.FLOAT
        acc = g.Accessor(
            bufferView=len(gl.bufferViews) - 1,
            componentType=ctype,
            count=len(a),
            type=kind,
        )
        if kind == g.VEC3 and ctype == g.FLOAT:
            acc.min = a.min(axis=0).tolist()
            acc.max = a.max(axis=0).tolist()
        gl.accessors.append(acc)


def quad(size=1.0, y=0.0):
    s = size
    pos = np.array([[-s, y, -s], [s, y, -s], [s, y, s], [-s, y, s]], dtype=np.float32)
    nrm = np.array([[0, 1, 0]] * 4, dtype=np.float32)
    idx = np.array([0, 2, 1, 0, 3, 2], dtype=np.uint32)
    return pos, nrm, idx


def hierarchy():
    pos, nrm, idx = quad(0.5)
    # The second primitive: a triangle without indices, with vertex colours.
    tri = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    col = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
    arrays = [pos, nrm, idx, tri, col]
    blob, spans = pack(arrays)
    gl = g.GLTF2()
    gl.buffers.append(
        g.Buffer(byteLength=len(blob), uri="data:application/octet-stream;base64," + base64.b64encode(blob).decode())
    )
    accessors(gl, spans, arrays, [g.VEC3, g.VEC3, g.SCALAR, g.VEC3, g.VEC3],
              [g.ARRAY_BUFFER, g.ARRAY_BUFFER, g.ELEMENT_ARRAY_BUFFER, g.ARRAY_BUFFER, g.ARRAY_BUFFER])
    gl.materials.append(
        g.Material(
            name="brushed",
            pbrMetallicRoughness=g.PbrMetallicRoughness(
                baseColorFactor=[0.8, 0.6, 0.2, 1.0], metallicFactor=0.7, roughnessFactor=0.3
            ),
            doubleSided=True,
        )
    )
    gl.meshes.append(
        g.Mesh(
            name="quad",
            primitives=[
                g.Primitive(attributes=g.Attributes(POSITION=0, NORMAL=1), indices=2, material=0),
                g.Primitive(attributes=g.Attributes(POSITION=3, COLOR_0=4)),
            ],
        )
    )
    s = math.sqrt(0.5)
    child = g.Node(
        name="child",
        mesh=0,
        matrix=[0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 1, 0, 1],
    )
    gl.nodes.append(g.Node(name="parent", rotation=[0, s, 0, s], translation=[2, 0, 0], children=[1]))
    gl.nodes.append(child)
    gl.scenes.append(g.Scene(nodes=[0]))
    gl.scene = 0
    gl.save("hierarchy.gltf")


def camera_lights():
    pos, nrm, idx = quad(2.0)
    arrays = [pos, nrm, idx]
    blob, spans = pack(arrays)
    with open("camera_lights.bin", "wb") as f:
        f.write(blob)
    gl = g.GLTF2()
    gl.buffers.append(g.Buffer(byteLength=len(blob), uri="camera_lights.bin"))
    accessors(gl, spans, arrays, [g.VEC3, g.VEC3, g.SCALAR],
              [g.ARRAY_BUFFER, g.ARRAY_BUFFER, g.ELEMENT_ARRAY_BUFFER])
    gl.materials.append(
        g.Material(name="floor", pbrMetallicRoughness=g.PbrMetallicRoughness(baseColorFactor=[0.5, 0.5, 0.5, 1.0],
                                                                             metallicFactor=0.0, roughnessFactor=0.8))
    )
    gl.meshes.append(g.Mesh(primitives=[g.Primitive(attributes=g.Attributes(POSITION=0, NORMAL=1), indices=2, material=0)]))
    gl.cameras.append(
        g.Camera(type="perspective", perspective=g.Perspective(yfov=math.radians(45), aspectRatio=1.5, znear=0.1, zfar=100))
    )
    gl.extensionsUsed = ["KHR_lights_punctual"]
    gl.extensions = {
        "KHR_lights_punctual": {
            "lights": [
                {"type": "point", "color": [1.0, 0.9, 0.8], "intensity": 100.0},
                {"type": "spot", "intensity": 50.0, "spot": {"innerConeAngle": math.radians(10), "outerConeAngle": math.radians(30)}},
                {"type": "directional", "intensity": 3.0},
            ]
        }
    }
    down = [-math.sqrt(0.5), 0, 0, math.sqrt(0.5)]  # -90 degrees about x: -z becomes -y
    gl.nodes += [
        g.Node(name="floor", mesh=0),
        g.Node(name="camera", camera=0, translation=[0, 1, 5]),
        g.Node(name="point", translation=[0, 3, 0], extensions={"KHR_lights_punctual": {"light": 0}}),
        g.Node(name="spot", translation=[1, 3, 0], rotation=down, extensions={"KHR_lights_punctual": {"light": 1}}),
        g.Node(name="sun", rotation=down, extensions={"KHR_lights_punctual": {"light": 2}}),
    ]
    gl.scenes.append(g.Scene(nodes=[0, 1, 2, 3, 4]))
    gl.scene = 0
    gl.save("camera_lights.gltf")


def ortho():
    tri = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    blob, spans = pack([tri])
    gl = g.GLTF2()
    gl.buffers.append(
        g.Buffer(byteLength=len(blob), uri="data:application/octet-stream;base64," + base64.b64encode(blob).decode())
    )
    accessors(gl, spans, [tri], [g.VEC3], [g.ARRAY_BUFFER])
    gl.meshes.append(g.Mesh(primitives=[g.Primitive(attributes=g.Attributes(POSITION=0))]))
    gl.cameras.append(g.Camera(type="orthographic", orthographic=g.Orthographic(xmag=2, ymag=2, znear=0.01, zfar=10)))
    gl.nodes += [g.Node(mesh=0), g.Node(camera=0, translation=[0.3, 0.3, 3])]
    gl.scenes.append(g.Scene(nodes=[0, 1]))
    gl.scene = 0
    gl.save("ortho.gltf")


def extensions():
    pos, nrm, idx = quad(1.0)
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float32)
    arrays = [pos, nrm, idx, uv]
    blob, spans = pack(arrays)
    gl = g.GLTF2()
    gl.buffers.append(
        g.Buffer(byteLength=len(blob), uri="data:application/octet-stream;base64," + base64.b64encode(blob).decode())
    )
    accessors(gl, spans, arrays, [g.VEC3, g.VEC3, g.SCALAR, g.VEC2],
              [g.ARRAY_BUFFER, g.ARRAY_BUFFER, g.ELEMENT_ARRAY_BUFFER, g.ARRAY_BUFFER])
    img = Image.new("RGB", (4, 4))
    for y in range(4):
        for x in range(4):
            img.putpixel((x, y), (200, 60, 20) if (x + y) % 2 else (250, 250, 250))
    img.save("checker.png")
    gl.images.append(g.Image(uri="checker.png"))
    gl.samplers.append(g.Sampler())
    gl.textures.append(g.Texture(source=0, sampler=0))
    transform = {"KHR_texture_transform": {"offset": [0.5, 0.25], "rotation": 0.3, "scale": [2.0, 3.0]}}
    gl.materials.append(
        g.Material(
            name="lamp_glass",
            pbrMetallicRoughness=g.PbrMetallicRoughness(
                baseColorFactor=[0.5, 1.0, 1.0, 1.0],
                baseColorTexture=g.TextureInfo(index=0, extensions=transform),
                metallicFactor=0.0,
                roughnessFactor=0.2,
            ),
            emissiveTexture=g.TextureInfo(index=0),
            emissiveFactor=[1.0, 0.5, 0.25],
            extensions={
                "KHR_materials_emissive_strength": {"emissiveStrength": 4.0},
                "KHR_materials_transmission": {"transmissionFactor": 0.8},
                "KHR_materials_ior": {"ior": 1.33},
            },
        )
    )
    gl.meshes.append(g.Mesh(primitives=[g.Primitive(attributes=g.Attributes(POSITION=0, NORMAL=1, TEXCOORD_0=3), indices=2, material=0)]))
    gl.nodes.append(g.Node(mesh=0))
    gl.scenes.append(g.Scene(nodes=[0]))
    gl.scene = 0
    gl.extensionsUsed = ["KHR_texture_transform", "KHR_materials_emissive_strength",
                         "KHR_materials_transmission", "KHR_materials_ior"]
    gl.save("extensions.gltf")


if __name__ == "__main__":
    textured_box()
    hierarchy()
    camera_lights()
    ortho()
    extensions()
