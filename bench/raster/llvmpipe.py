#!/usr/bin/env python3
"""The peer of docs/benchmarks/raster.md: Mesa llvmpipe (OpenGL on the CPU) through
moderngl, drawing the workload file written by `raster_bench write`.

    LP_NUM_THREADS=2 python3 llvmpipe.py FILE FRAMES [PNG]

Same triangles, view, light and per-vertex (Gouraud, two-sided) lighting as Irradia.
The vertex and index buffers are uploaded once; after one untimed warm-up frame,
a timed frame is `fbo.clear(); vao.render(); fbo.read(); ctx.finish()` (read back the 1280x720 RGBA8 image, which
waits for llvmpipe to finish the frame). Prints one JSON line: wall time per frame
(median_s) and process CPU time per frame, all threads (cpu_median_s).
"""
import json
import os
import struct
import sys
import time

import numpy as np

try:
    import moderngl
except ImportError:  # skip cleanly
    print(json.dumps({"renderer": "llvmpipe", "skipped": "moderngl is not installed"}))
    sys.exit(0)

VS = """
#version 330
uniform mat4 view;
uniform mat4 proj;
uniform vec3 to_light;   // eye space, unit
uniform vec3 light;
uniform vec3 ambient;
uniform vec3 diffuse;
in vec3 in_pos;
in vec3 in_normal;
out vec3 color;
void main() {
    vec4 pe = view * vec4(in_pos, 1.0);
    vec3 n = normalize(mat3(view) * in_normal);
    vec3 to_eye = normalize(-pe.xyz);
    if (dot(n, to_eye) < 0.0) n = -n;
    color = diffuse * (ambient + light * max(dot(n, to_light), 0.0));
    gl_Position = proj * pe;
}
"""
FS = """
#version 330
in vec3 color;
out vec4 frag;
void main() { frag = vec4(color, 1.0); }
"""


def look_at(eye, target, up):
    f = target - eye
    f = f / np.linalg.norm(f)
    s = np.cross(f, up)
    s = s / np.linalg.norm(s)
    u = np.cross(s, f)
    m = np.identity(4, dtype=np.float32)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[0, 3], m[1, 3], m[2, 3] = -s.dot(eye), -u.dot(eye), f.dot(eye)
    return m


def perspective(fovy_deg, aspect, near, far):
    t = 1.0 / np.tan(np.radians(fovy_deg) / 2)
    m = np.zeros((4, 4), dtype=np.float32)
    m[0, 0], m[1, 1] = t / aspect, t
    m[2, 2], m[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def load(path):
    b = open(path, "rb").read()
    assert b[:4] == b"IRRT", f"{path}: not a raster_bench workload"
    w, h = struct.unpack_from("<2I", b, 4)
    fl = np.frombuffer(b, "<f4", 24, 12)
    nv, nt = struct.unpack_from("<2I", b, 12 + 96)
    at = 12 + 96 + 8
    pos = np.frombuffer(b, "<f4", 3 * nv, at).reshape(nv, 3)
    at += 12 * nv
    nrm = np.frombuffer(b, "<f4", 3 * nv, at).reshape(nv, 3)
    at += 12 * nv
    idx = np.frombuffer(b, "<u4", 3 * nt, at)
    return w, h, fl, pos, nrm, idx


def main():
    path, frames = sys.argv[1], int(sys.argv[2])
    png = sys.argv[3] if len(sys.argv) > 3 else None
    w, h, fl, pos, nrm, idx = load(path)
    eye, target, up = fl[0:3], fl[3:6], fl[6:9]
    fovy, near, far = fl[9], fl[10], fl[11]
    light_dir, light, ambient, diffuse = fl[12:15], fl[15:18], fl[18:21], fl[21:24]
    ctx = moderngl.create_standalone_context(backend="egl")
    prog = ctx.program(vertex_shader=VS, fragment_shader=FS)
    view = look_at(eye.astype(np.float64), target.astype(np.float64), up.astype(np.float64))
    prog["view"].write(view.T.astype("f4").tobytes())
    prog["proj"].write(perspective(fovy, w / h, near, far).T.astype("f4").tobytes())
    to_light = -(view[:3, :3] @ light_dir)
    prog["to_light"].value = tuple(to_light / np.linalg.norm(to_light))
    prog["light"].value = tuple(light)
    prog["ambient"].value = tuple(ambient)
    prog["diffuse"].value = tuple(diffuse)
    vbo = ctx.buffer(np.hstack([pos, nrm]).astype("f4").tobytes())
    ibo = ctx.buffer(idx.astype("u4").tobytes())
    vao = ctx.vertex_array(prog, [(vbo, "3f 3f", "in_pos", "in_normal")], ibo, index_element_size=4)
    fbo = ctx.simple_framebuffer((w, h), components=4)
    fbo.use()
    ctx.enable(moderngl.DEPTH_TEST)
    times = []
    cpus = []  # process CPU time per frame, all threads (llvmpipe's and this one's)
    data = None
    for frame in range(frames + 1):  # one untimed warm-up frame (shader JIT, first touch)
        t0 = time.perf_counter()
        c0 = time.process_time()
        fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
        vao.render(moderngl.TRIANGLES)
        data = fbo.read(components=4)
        ctx.finish()
        if frame > 0:
            times.append(time.perf_counter() - t0)
            cpus.append(time.process_time() - c0)
    if png:
        from PIL import Image

        img = np.frombuffer(data, np.uint8).reshape(h, w, 4)[::-1]
        Image.fromarray(img, "RGBA").save(png)
    s = sorted(times)
    print(json.dumps({"renderer": "llvmpipe", "threads": int(os.environ.get("LP_NUM_THREADS", "0")),
                      "frames": frames, "median_s": s[len(s) // 2], "min_s": s[0],
                      "cpu_median_s": sorted(cpus)[len(cpus) // 2], "times": times, "cpus": cpus}))


if __name__ == "__main__":
    main()
