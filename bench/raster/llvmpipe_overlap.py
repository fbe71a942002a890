#!/usr/bin/env python3
"""Whether llvmpipe's threads overlap within a frame (why bench/raster/run.sh pins its
1-thread runs to one core).

    LP_NUM_THREADS=1 python3 bench/raster/llvmpipe_overlap.py FILE FRAMES

Draws the workload as llvmpipe.py does and prints, per frame, the CPU time (schedstat
run time) of the application thread and of the rasterizer thread(s) inside
`vao.render()` (the application thread transforms and bins; rasterizer time there runs
alongside it) and inside `fbo.read(); ctx.finish()` (the rasterizers finish the frame).
"""
import os, sys, time
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np, moderngl
import llvmpipe as L
def run_ns():
    """Run time in ns per thread name (rasterizer threads are named llvmpipe-N)."""
    out = {}
    for t in os.listdir("/proc/self/task"):
        s = open(f"/proc/self/task/{t}/stat").read()
        name = s[s.index("(")+1:s.rindex(")")]
        out[name] = out.get(name, 0) + int(open(f"/proc/self/task/{t}/schedstat").read().split()[0])
    return out
path, frames = sys.argv[1], int(sys.argv[2])
w, h, fl, pos, nrm, idx = L.load(path)
eye, target, up = fl[0:3], fl[3:6], fl[6:9]
fovy, near, far = fl[9], fl[10], fl[11]
light_dir, light, ambient, diffuse = fl[12:15], fl[15:18], fl[18:21], fl[21:24]
ctx = moderngl.create_standalone_context(backend="egl")
prog = ctx.program(vertex_shader=L.VS, fragment_shader=L.FS)
view = L.look_at(eye.astype(np.float64), target.astype(np.float64), up.astype(np.float64))
prog["view"].write(view.T.astype("f4").tobytes())
prog["proj"].write(L.perspective(fovy, w / h, near, far).T.astype("f4").tobytes())
tl = -(view[:3, :3] @ light_dir); prog["to_light"].value = tuple(tl / np.linalg.norm(tl))
prog["light"].value = tuple(light); prog["ambient"].value = tuple(ambient); prog["diffuse"].value = tuple(diffuse)
vbo = ctx.buffer(np.hstack([pos, nrm]).astype("f4").tobytes())
ibo = ctx.buffer(idx.astype("u4").tobytes())
vao = ctx.vertex_array(prog, [(vbo, "3f 3f", "in_pos", "in_normal")], ibo, index_element_size=4)
fbo = ctx.simple_framebuffer((w, h), components=4); fbo.use(); ctx.enable(moderngl.DEPTH_TEST)
for f in range(frames + 1):
    a = run_ns(); t0 = time.perf_counter()
    fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0); vao.render(moderngl.TRIANGLES)
    b = run_ns(); t1 = time.perf_counter()
    fbo.read(components=4); ctx.finish()
    c = run_ns(); t2 = time.perf_counter()
    d = lambda x, y, k: (y.get(k, 0) - x.get(k, 0)) / 1e9
    rast = lambda x, y: sum(d(x, y, k) for k in y if k.startswith("llvmpipe-"))
    if f: print(f"render() {t1-t0:.3f} s wall: app {d(a,b,'python3'):.3f} raster {rast(a,b):.3f} CPU s | read+finish {t2-t1:.3f} s wall: app {d(b,c,'python3'):.3f} raster {rast(b,c):.3f}")
