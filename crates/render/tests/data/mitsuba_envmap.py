"""Writes mitsuba_envmap.csv: Mitsuba 3's `envmap` emitter (pip Mitsuba 3.9.1, scalar_rgb)
on crates/scene/tests/data/emitters/sky.hdr (16 x 8) with scale 1.5 and a rotation,
evaluated at fixed world directions: the radiance a ray travelling along `d` sees
(`eval` with si.wi = -d) and the solid-angle density of sampling `d`
(`pdf_direction`). Run from this folder: python3 mitsuba_envmap.py."""
import os
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
here = os.path.dirname(os.path.abspath(__file__))
sky = os.path.join(here, "..", "..", "..", "scene", "tests", "data", "emitters", "sky.hdr")
T = mi.ScalarTransform4f
emitter = mi.load_dict({
    "type": "envmap",
    "filename": sky,
    "scale": 1.5,
    "to_world": T().rotate([0, 1, 0], 30).rotate([1, 0, 0], -20),
})
rng = np.random.default_rng(7)
rows = []
dirs = [np.array(v, float) for v in ([0, 1, 0], [0, -1, 0], [0, 0, -1], [1, 0, 0], [0.3, 0.9, 0.1])]
while len(dirs) < 64:
    v = rng.normal(size=3)
    dirs.append(v / np.linalg.norm(v))
for d in dirs:
    d = d / np.linalg.norm(d)
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(*(-d))
    L = emitter.eval(si)
    it = mi.Interaction3f()
    ds = mi.DirectionSample3f()
    ds.d = mi.Vector3f(*d)
    pdf = emitter.pdf_direction(it, ds)
    rows.append([*d, L[0], L[1], L[2], float(pdf)])
with open(os.path.join(here, "mitsuba_envmap.csv"), "w") as f:
    f.write("# Mitsuba 3.9.1 scalar_rgb envmap on sky.hdr, scale 1.5, to_world = rotate y 30 then x -20 (Mitsuba's order)\n")
    f.write("dx,dy,dz,r,g,b,pdf\n")
    for r in rows:
        f.write(",".join(f"{x:.9g}" for x in r) + "\n")
print(len(rows), "rows")
