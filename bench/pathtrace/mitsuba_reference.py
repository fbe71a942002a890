#!/usr/bin/env python3
"""Mitsuba 3 reference values for crates/render/tests/path_mitsuba.rs.

Renders two scenes with Mitsuba 3 (variant scalar_rgb, `path` integrator, max depth 8,
box pixel filter, independent sampler) and stores, per surface, the mean radiance of
each RGB channel over the surface's pixels and the standard error of that mean,
estimated from the spread of renders made with independent seeds (not from the spread
of pixels: radiance varies across a surface):

  * `cornell`: the built-in scene of that name, Mitsuba's `mi.cornell_box()` (the same
    dict bench/pathtrace/compare.py uses);
  * `cornell_specular`: crates/render/tests/data/cornell_specular.toml, the walls of the
    Cornell box with a larger light, a clear glass sphere (ior 1.5), a perfect mirror
    sphere and a smooth-shaded triangle mesh (torus.obj, vertex normals), built here as
    the Mitsuba dict `cornell_specular()`.

The surfaces are Irradia's objects: masks from Irradia's object-id AOV (Whitted
integrator, 1 spp, so the pixel centres; `irradia render --aov object-id`), eroded by
2 pixels so that no pixel of a mask mixes two surfaces (outside the image counts as
another surface). The masks are stored with the values, as one string per image row.
Before rendering, the script checks that the two descriptions of each scene are the
same geometry: Mitsuba's first-hit distance and shading normal (AOV integrator) must
match Irradia's depth and normal AOVs on every mask pixel.

Usage: python3 bench/pathtrace/mitsuba_reference.py [--res 96] [--spp 1024]
       [--seeds 16] [--threads 2] [--out crates/render/tests/data/mitsuba_reference.json]
       [--write-mesh]
Installs Mitsuba with pip when it is missing; skips cleanly (exit 0) when it cannot.
"""
import argparse, datetime, json, math, os, subprocess, sys, tempfile, time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(ROOT, "crates", "render", "tests", "data")
MITSUBA_VERSION, DRJIT_VERSION = "3.9.1", "1.5.0"
VARIANT = "scalar_rgb"
MAX_DEPTH = 8
ERODE = 2

# Irradia object names in scene order (object-id = index), per scene.
CORNELL_OBJECTS = ["floor", "ceiling", "back wall", "red wall", "green wall", "light", "tall box", "short box"]
SPECULAR_OBJECTS = ["floor", "ceiling", "back wall", "red wall", "green wall", "light", "glass sphere",
                    "mirror sphere", "torus"]

# The torus of cornell_specular (world coordinates baked into torus.obj).
TORUS = dict(center=(0.5, -0.55, 0.4), axis=(-0.3, 0.45, 1.0), major=0.27, minor=0.12, nt=24, np=12)


def ensure_mitsuba():
    try:
        import mitsuba  # noqa: F401
        return True
    except ImportError:
        r = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "numpy", f"mitsuba=={MITSUBA_VERSION}",
                            f"drjit=={DRJIT_VERSION}"])
        if r.returncode != 0:
            print("SKIP: mitsuba could not be installed")
            return False
        try:
            import mitsuba  # noqa: F401
            return True
        except ImportError:
            print("SKIP: mitsuba installed but cannot be imported")
            return False


def torus_obj():
    """The OBJ text of the torus: 24 x 12 quads as triangles, wound so that the face
    normals point outwards, with the exact (analytic) vertex normals."""
    import numpy as np
    t = TORUS
    c = np.array(t["center"], float)
    a = np.array(t["axis"], float)
    a /= np.linalg.norm(a)
    u = np.array([1.0, 0.0, 0.0]) - a * a[0]
    u /= np.linalg.norm(u)
    v = np.cross(a, u)
    vs, ns = [], []
    for i in range(t["nt"]):
        th = 2 * math.pi * i / t["nt"]
        radial = math.cos(th) * u + math.sin(th) * v
        for j in range(t["np"]):
            ph = 2 * math.pi * j / t["np"]
            n = math.cos(ph) * radial + math.sin(ph) * a
            vs.append(c + t["major"] * radial + t["minor"] * n)
            ns.append(n)
    idx = lambda i, j: (i % t["nt"]) * t["np"] + (j % t["np"])
    faces = []
    for i in range(t["nt"]):
        for j in range(t["np"]):
            q = [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]
            faces += [(q[0], q[1], q[2]), (q[0], q[2], q[3])]
    for f in faces:
        p0, p1, p2 = (vs[k] for k in f)
        assert np.dot(np.cross(p1 - p0, p2 - p0), sum(ns[k] for k in f)) > 0, "inward face"
    lines = [
        "# A torus for the Mitsuba comparison (crates/render/tests/path_mitsuba.rs): centre "
        f"{list(t['center'])}, axis {list(t['axis'])} (normalised),",
        f"# major radius {t['major']}, minor radius {t['minor']}, {t['nt']} x {t['np']} quads as {len(faces)} "
        "triangles, world coordinates,",
        "# exact vertex normals (smooth shading). Written by bench/pathtrace/mitsuba_reference.py --write-mesh.",
    ]
    lines += ["v %.6f %.6f %.6f" % tuple(p) for p in vs]
    lines += ["vn %.6f %.6f %.6f" % tuple(n) for n in ns]
    lines += ["f %d//%d %d//%d %d//%d" % (f[0] + 1, f[0] + 1, f[1] + 1, f[1] + 1, f[2] + 1, f[2] + 1) for f in faces]
    return "\n".join(lines) + "\n"


def rgb(v):
    return {"type": "rgb", "value": list(v)}


def sensor_setup(d, res, spp):
    d["sensor"]["film"]["width"] = res
    d["sensor"]["film"]["height"] = res
    d["sensor"]["film"]["rfilter"] = {"type": "box"}
    d["sensor"]["sampler"] = {"type": "independent", "sample_count": spp}
    d["integrator"] = {"type": "path", "max_depth": MAX_DEPTH}
    return d


def cornell(res, spp):
    import mitsuba as mi
    return sensor_setup(mi.cornell_box(), res, spp)


def cornell_specular(res, spp):
    """crates/render/tests/data/cornell_specular.toml as a Mitsuba dict: the walls, the
    camera and the materials of mi.cornell_box(), a 1 x 0.8 light at y = 0.99 facing
    down, a glass sphere, a mirror sphere and the torus mesh."""
    import mitsuba as mi
    d = mi.cornell_box()
    for k in ("large-box", "small-box", "light"):
        del d[k]
    T = mi.ScalarTransform4f
    d["light"] = {
        "type": "rectangle",
        # The unit square [-1,1]^2 (normal +z) scaled to 0.5 x 0.4, turned so +z -> -y.
        "to_world": T().translate([0.0, 0.99, 0.0]) @ T().rotate([1, 0, 0], 90) @ T().scale([0.5, 0.4, 1.0]),
        "bsdf": {"type": "ref", "id": "white"},
        "emitter": {"type": "area", "radiance": rgb([4.0, 3.2, 1.6])},
    }
    d["glass-sphere"] = {
        "type": "sphere", "center": [-0.4, -0.62, 0.3], "radius": 0.36,
        "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
    }
    d["mirror-sphere"] = {
        "type": "sphere", "center": [0.05, -0.56, -0.45], "radius": 0.44,
        "bsdf": {"type": "conductor", "material": "none"},
    }
    d["torus"] = {
        "type": "obj", "filename": os.path.join(DATA, "torus.obj"), "face_normals": False,
        "bsdf": {"type": "diffuse", "reflectance": rgb([0.3, 0.5, 0.8])},
    }
    return sensor_setup(d, res, spp)


SCENES = {
    "cornell": dict(build=cornell, objects=CORNELL_OBJECTS, irradia=["--builtin", "cornell"],
                    irradia_name="builtin:cornell", mitsuba="mi.cornell_box()"),
    "cornell_specular": dict(build=cornell_specular, objects=SPECULAR_OBJECTS,
                             irradia=[os.path.join(DATA, "cornell_specular.toml")],
                             irradia_name="crates/render/tests/data/cornell_specular.toml",
                             mitsuba="cornell_specular() in bench/pathtrace/mitsuba_reference.py"),
}


def irradia_binary():
    """The release binary, built first; or `IRRADIA_BIN` (a copy of another build), as is."""
    if os.environ.get("IRRADIA_BIN"):
        return os.environ["IRRADIA_BIN"]
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "irradia"], cwd=ROOT, check=True)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "irradia")


def read_pfm(path):
    import numpy as np
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return data[::-1].copy()


def irradia_aovs(binary, scene_args, res, tmp):
    """Irradia's object ids, depths and normals at the pixel centres (Whitted, 1 spp)."""
    import numpy as np
    out = os.path.join(tmp, "aov.pfm")
    subprocess.run([binary, "render", *scene_args, "--integrator", "whitted", "--spp", "1", "--width", str(res),
                    "--height", str(res), "--quiet", "--aov", "object-id,depth,normal", "-o", out], check=True)
    ids = np.rint(read_pfm(os.path.join(tmp, "aov.object-id.pfm"))[..., 0]).astype(int)
    depth = read_pfm(os.path.join(tmp, "aov.depth.pfm"))[..., 0]
    normal = read_pfm(os.path.join(tmp, "aov.normal.pfm"))
    return ids, depth, normal


def eroded_labels(ids, r=ERODE):
    """Per pixel: the object id where every pixel within r (Chebyshev) has that id and lies
    inside the image, else -1."""
    import numpy as np
    h, w = ids.shape
    pad = np.full((h + 2 * r, w + 2 * r), -2, dtype=int)
    pad[r:r + h, r:r + w] = ids
    keep = ids >= 0
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            keep &= pad[r + dy:r + dy + h, r + dx:r + dx + w] == ids
    return np.where(keep, ids, -1)


def label_rows(labels):
    return ["".join("." if v < 0 else chr(ord("0") + int(v)) for v in row) for row in labels]


def check_geometry(d, labels, depth, normal):
    """Mitsuba's first hits against Irradia's on the mask pixels: the distance and the
    shading normal averaged over each pixel (Mitsuba) against the pixel centre's
    (Irradia). They agree to the variation within a pixel; a pixel whose area straddles
    two faces of one object (a box's edge) averages two normals, so the check counts
    the pixels that agree closely and requires nearly all of them to."""
    import mitsuba as mi
    import numpy as np
    d = dict(d)
    d["integrator"] = {"type": "aov", "aovs": "dd:depth,nn:sh_normal"}
    img = np.array(mi.render(mi.load_dict(d), spp=64, seed=12345))
    m_depth, m_normal = img[..., 0], img[..., 1:4]
    sel = labels >= 0
    m_normal = m_normal[sel] / np.maximum(np.linalg.norm(m_normal[sel], axis=-1, keepdims=True), 1e-12)
    rel = np.abs(m_depth[sel] - depth[sel]) / depth[sel]
    dots = np.sum(m_normal * normal[sel], axis=-1)
    close = (rel < 0.01) & (dots > 0.99)
    return {"pixels": int(sel.sum()), "agreeing_fraction": float(close.mean()),
            "median_rel_depth_diff": float(np.median(rel)), "max_rel_depth_diff": float(rel.max()),
            "median_normal_dot": float(np.median(dots)), "min_normal_dot": float(dots.min()),
            "criterion": "agreeing: relative depth difference < 1% and normals' dot > 0.99; "
                         "required: 98% of the mask pixels"}


def surface_means(img, labels, ids):
    import numpy as np
    return np.array([img[labels == i].mean(axis=0) for i in ids])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--res", type=int, default=96)
    ap.add_argument("--spp", type=int, default=1024, help="samples per pixel of each seed's render")
    ap.add_argument("--seeds", type=int, default=16, help="independent renders (seeds 0..N-1)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scenes", default="cornell,cornell_specular")
    ap.add_argument("--out", default=os.path.join(DATA, "mitsuba_reference.json"))
    ap.add_argument("--write-mesh", action="store_true", help="(re)write crates/render/tests/data/torus.obj")
    a = ap.parse_args()
    mesh_path = os.path.join(DATA, "torus.obj")
    if not ensure_mitsuba():
        return 0
    import numpy as np
    import mitsuba as mi
    import drjit as dr
    if a.write_mesh:
        with open(mesh_path, "w") as f:
            f.write(torus_obj())
    with open(mesh_path) as f:
        if f.read() != torus_obj():
            print(f"error: {mesh_path} is not the torus this script makes (run with --write-mesh)")
            return 1
    mi.set_variant(VARIANT)
    dr.set_thread_count(a.threads)
    binary = irradia_binary()
    tmp = tempfile.mkdtemp()
    result = {
        "note": ("Mitsuba 3 reference values for crates/render/tests/path_mitsuba.rs, written by "
                 "bench/pathtrace/mitsuba_reference.py. Per scene and surface (an Irradia object): the mean "
                 "radiance of each RGB channel over the surface's mask pixels, averaged over independent "
                 "renders, and the standard error of that mean (sample standard deviation of the per-render "
                 "surface means / sqrt(renders)). Masks: Irradia's object-id AOV at the pixel centres, eroded by "
                 "2 pixels (outside the image counts as another surface); `labels` holds them, one string per "
                 "image row from the top, the character '0' + object index or '.' for no mask."),
        "mitsuba": {
            "version": mi.__version__, "drjit": dr.__version__, "variant": VARIANT, "integrator": "path",
            "max_depth": MAX_DEPTH, "rr_depth": 5, "hide_emitters": False, "rfilter": "box",
            "sampler": "independent", "width": a.res, "height": a.res, "spp_per_render": a.spp,
            "seeds": list(range(a.seeds)), "threads": a.threads,
        },
        "made": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "scenes": {},
    }
    for name in a.scenes.split(","):
        sc = SCENES[name]
        ids, depth, normal = irradia_aovs(binary, sc["irradia"], a.res, tmp)
        labels = eroded_labels(ids)
        d = sc["build"](a.res, a.spp)
        geo = check_geometry(d, labels, depth, normal)
        print(f"{name}: geometry against Irradia on {geo['pixels']} mask pixels: "
              f"{geo['agreeing_fraction'] * 100:.2f} % agree; depth median {geo['median_rel_depth_diff']:.1e} "
              f"max {geo['max_rel_depth_diff']:.1e} (relative), normals' dot median "
              f"{geo['median_normal_dot']:.5f} min {geo['min_normal_dot']:.4f}")
        if geo["agreeing_fraction"] < 0.98:
            print(f"error: the Mitsuba and Irradia descriptions of {name} differ")
            return 1
        present = [i for i in range(len(sc["objects"])) if (labels == i).any()]
        scene = mi.load_dict(d)
        per_seed = []
        t0 = time.perf_counter()
        for seed in range(a.seeds):
            img = np.array(mi.render(scene, spp=a.spp, seed=seed), dtype=np.float64)[..., :3]
            per_seed.append(surface_means(img, labels, present))
            print(f"  {name} seed {seed}: {time.perf_counter() - t0:.0f} s", flush=True)
        per_seed = np.array(per_seed)  # seeds x surfaces x 3
        mean = per_seed.mean(axis=0)
        se = per_seed.std(axis=0, ddof=1) / math.sqrt(a.seeds)
        surfaces = []
        for k, i in enumerate(present):
            surfaces.append({"name": sc["objects"][i], "object": i, "pixels": int((labels == i).sum()),
                             "mean": [float(x) for x in mean[k]], "se": [float(x) for x in se[k]]})
            print(f"  {sc['objects'][i]:13s} px {surfaces[-1]['pixels']:5d}  mean {np.round(mean[k], 5)}  "
                  f"se/mean {np.round(se[k] / mean[k] * 100, 3)} %")
        result["scenes"][name] = {
            "irradia": sc["irradia_name"], "mitsuba": sc["mitsuba"],
            "render_seconds": round(time.perf_counter() - t0, 1),
            "geometry_check": geo, "labels": label_rows(labels), "surfaces": surfaces,
        }
    with open(a.out, "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
