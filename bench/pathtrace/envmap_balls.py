#!/usr/bin/env python3
"""Agreement with Mitsuba 3 on balls of physically based materials under an environment
map: a rough conductor (gold, GGX, alpha 0.2), a rough dielectric (BK7 in air, GGX,
alpha 0.2), a plastic (Mitsuba's bsdf_spheres "plastic shiny": diffuse 0.1, 0.27,
0.36, int_ior 1.9), an anisotropic rough aluminium (alpha_u 0.05, alpha_v 0.3: the
tangent frame along Mitsuba's dp/du), and Mitsuba's test normal map (on rough gold)
and bump map (scale 0.02, on a diffuse), each alone under Mitsuba's `museum.exr` (the envmap of Mitsuba's own
render tests), rendered by Irradia's path tracer and Mitsuba's `path` integrator
(scalar_rgb) with the same camera, box pixel filter, max depth and samples per pixel.

The scenes are written twice, as an Irradia TOML file and as a Mitsuba dict, from the
one table MATERIALS below; the script first checks that both describe the same geometry
(Mitsuba's first-hit depth and normal against Irradia's AOVs). The image is then cut
into regions: the ball's pixels (Irradia's object-id AOV, eroded by 2 pixels) in a 3 x 3
grid over its bounding box, and the background (the environment seen directly) in four
quadrants. For each region and RGB channel, the mean radiance of S independent renders
of each renderer (Irradia `--seed 1..S`, Mitsuba seeds 0..S-1), its standard error from
the spread of the S renders, and the relative difference. A region agrees when the
difference is within 1% of Mitsuba's value (the goal of issue 12); z, the difference in
combined standard errors, says whether what is left is noise.

Usage: python3 bench/pathtrace/envmap_balls.py [--res 128] [--spp 256] [--seeds 4]
       [--threads 2] [--max-depth 16] [--envmap PATH] [--json OUT]
Installs Mitsuba with pip when it is missing; skips cleanly (exit 0) when it cannot or
when the envmap is not there.
"""
import argparse, json, os, subprocess, sys, tempfile, time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from mitsuba_reference import (ROOT, ensure_mitsuba, eroded_labels, irradia_aovs,  # noqa: E402
                               irradia_binary, read_pfm, check_geometry)

TEXTURES = os.path.join(ROOT, "..", "shared", "mitsuba-data", "common", "textures")
ENVMAP = os.path.join(TEXTURES, "museum.exr")
NORMALMAP = os.path.join(TEXTURES, "floor_tiles_normalmap.jpg")
BUMPMAP = os.path.join(TEXTURES, "floor_tiles_bumpmap.png")
EYE, TARGET, UP, FOV = (0.0, 0.6, 3.4), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0), 45.0

# name -> (Irradia material table as TOML lines, Mitsuba BSDF dict): the same parameters.
MATERIALS = {
    "roughconductor": (
        ['type = "roughconductor"', 'material = "Au"', 'distribution = "ggx"', "alpha = 0.2"],
        {"type": "roughconductor", "material": "Au", "distribution": "ggx", "alpha": 0.2},
    ),
    "roughdielectric": (
        ['type = "roughdielectric"', 'distribution = "ggx"', "alpha = 0.2", 'int_ior = "bk7"', 'ext_ior = "air"'],
        {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.2, "int_ior": "bk7", "ext_ior": "air"},
    ),
    "plastic": (
        ['type = "plastic"', "diffuse_reflectance = [0.1, 0.27, 0.36]", "int_ior = 1.9"],
        {"type": "plastic", "diffuse_reflectance": {"type": "rgb", "value": [0.1, 0.27, 0.36]}, "int_ior": 1.9},
    ),
    # The tangent frame: anisotropic roughness along dp/du of Mitsuba's sphere.
    "anisotropic": (
        ['type = "roughconductor"', 'material = "Al"', 'distribution = "ggx"', "alpha_u = 0.05", "alpha_v = 0.3"],
        {"type": "roughconductor", "material": "Al", "distribution": "ggx", "alpha_u": 0.05, "alpha_v": 0.3},
    ),
    # Mitsuba's bsdf_spheres normal map and bump map (its test textures) on rough gold.
    "normalmap": (
        ['type = "normalmap"', f'normalmap = {{ type = "bitmap", filename = "{NORMALMAP}", raw = true }}',
         'bsdf = { type = "roughconductor", material = "Au", distribution = "ggx", alpha = 0.1 }'],
        {"type": "normalmap", "normalmap": {"type": "bitmap", "filename": NORMALMAP, "raw": True},
         "bsdf": {"type": "roughconductor", "material": "Au", "distribution": "ggx", "alpha": 0.1}},
    ),
    "bumpmap": (
        ['type = "bumpmap"', "scale = 0.02", f'texture = {{ type = "bitmap", filename = "{BUMPMAP}", raw = true }}',
         'bsdf = { type = "diffuse", reflectance = [0.6, 0.5, 0.3] }'],
        {"type": "bumpmap", "scale": 0.02, "height": {"type": "bitmap", "filename": BUMPMAP, "raw": True},
         "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.6, 0.5, 0.3]}}},
    ),
}


def irradia_scene(name, envmap, res, spp, max_depth):
    mat = "\n".join(MATERIALS[name][0])
    return f"""# {name} ball under museum.exr (bench/pathtrace/envmap_balls.py)
[image]
width = {res}
height = {res}
filter = "box"

[camera]
eye = {list(EYE)}
look_at = {list(TARGET)}
up = {list(UP)}
fov = {FOV}
fov_axis = "x"

[render]
integrator = "path"
max_depth = {max_depth}
spp = {spp}
background = 0

[[lights]]
type = "envmap"
filename = "{envmap}"

[materials.ball]
{mat}

[[objects]]
name = "ball"
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "ball"
"""


def mitsuba_scene(name, envmap, res, spp, max_depth):
    import mitsuba as mi
    T = mi.ScalarTransform4f
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth},
        "sensor": {
            "type": "perspective", "fov": FOV, "fov_axis": "x", "near_clip": 0.01,
            "to_world": T().look_at(origin=list(EYE), target=list(TARGET), up=list(UP)),
            "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"},
                     "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "env": {"type": "envmap", "filename": envmap},
        "ball": {"type": "sphere", "center": [0, 0, 0], "radius": 1.0, "bsdf": MATERIALS[name][1]},
    }


def regions(ids):
    """Region masks: the eroded ball in a 3 x 3 grid of its bounding box, and the eroded
    background in four quadrants."""
    import numpy as np
    ball = eroded_labels(ids) == 0
    bg = eroded_labels(np.where(ids < 0, 0, 1)) == 0
    out = {}
    ys, xs = np.nonzero(ball)
    y_cuts = np.linspace(ys.min(), ys.max() + 1, 4)
    x_cuts = np.linspace(xs.min(), xs.max() + 1, 4)
    yy, xx = np.mgrid[0:ids.shape[0], 0:ids.shape[1]]
    for r in range(3):
        for c in range(3):
            m = ball & (yy >= y_cuts[r]) & (yy < y_cuts[r + 1]) & (xx >= x_cuts[c]) & (xx < x_cuts[c + 1])
            if m.sum() >= 20:
                out[f"ball {'tmb'[r]}{'lcr'[c]}"] = m
    h, w = ids.shape
    for r, top in enumerate((True, False)):
        for c, left in enumerate((True, False)):
            m = bg & ((yy < h // 2) == top) & ((xx < w // 2) == left)
            if m.sum() >= 20:
                out[f"sky {'tb'[r]}{'lr'[c]}"] = m
    return out


def stats(images, masks):
    """Per region: mean over renders of the region's mean RGB, and its standard error."""
    import numpy as np
    res = {}
    for k, m in masks.items():
        per = np.array([img[m].mean(axis=0) for img in images])
        res[k] = (per.mean(axis=0), per.std(axis=0, ddof=1) / np.sqrt(len(images)))
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--res", type=int, default=128)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--max-depth", type=int, default=16)
    ap.add_argument("--envmap", default=ENVMAP)
    ap.add_argument("--materials", default=",".join(MATERIALS))
    ap.add_argument("--json", help="also write the figures here")
    a = ap.parse_args()
    envmap = os.path.abspath(a.envmap)
    if not os.path.exists(envmap):
        print(f"SKIP: {envmap} not found (Mitsuba's test data, shared/mitsuba-data)")
        return 0
    if not ensure_mitsuba():
        return 0
    import numpy as np
    import mitsuba as mi
    import drjit as dr
    mi.set_variant("scalar_rgb")
    dr.set_thread_count(a.threads)
    binary = irradia_binary()
    tmp = tempfile.mkdtemp()
    report = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "mitsuba": mi.__version__,
              "variant": "scalar_rgb", "res": a.res, "spp": a.spp, "seeds": a.seeds, "max_depth": a.max_depth,
              "threads": a.threads, "scenes": {}}
    worst_all = 0.0
    for name in a.materials.split(","):
        path = os.path.join(tmp, f"{name}.toml")
        with open(path, "w") as f:
            f.write(irradia_scene(name, envmap, a.res, a.spp, a.max_depth))
        ids, depth, normal = irradia_aovs(binary, [path], a.res, tmp)
        d = mitsuba_scene(name, envmap, a.res, a.spp, a.max_depth)
        # The geometry alone (Mitsuba's shading-normal AOV would show a normal map).
        plain = dict(d, ball=dict(d["ball"], bsdf={"type": "diffuse"}))
        geo = check_geometry(plain, eroded_labels(ids), depth, normal)
        if geo["agreeing_fraction"] < 0.98:
            print(f"error: the Mitsuba and Irradia descriptions of {name} differ: {geo}")
            return 1
        masks = regions(ids)
        scene = mi.load_dict(d)
        t0 = time.perf_counter()
        m_imgs = [np.array(mi.render(scene, spp=a.spp, seed=s)) for s in range(a.seeds)]
        t_m = time.perf_counter() - t0
        i_imgs, t_i = [], 0.0
        for s in range(a.seeds):
            out = os.path.join(tmp, f"{name}-{s}.pfm")
            t0 = time.perf_counter()
            subprocess.run([binary, "render", path, "--seed", str(s + 1), "--threads", str(a.threads), "--quiet",
                            "-o", out], check=True)
            t_i += time.perf_counter() - t0
            i_imgs.append(read_pfm(out))
        mi_stats, ir_stats = stats(m_imgs, masks), stats(i_imgs, masks)
        rows, worst, worst_z = [], 0.0, 0.0
        for k in masks:
            (mm, ms), (im, se) = mi_stats[k], ir_stats[k]
            rel = (im - mm) / np.maximum(np.abs(mm), 1e-9)
            z = (im - mm) / np.sqrt(ms ** 2 + se ** 2 + 1e-30)
            worst = max(worst, float(np.abs(rel).max()))
            worst_z = max(worst_z, float(np.abs(z).max()))
            rows.append({"region": k, "pixels": int(masks[k].sum()), "mitsuba": mm.tolist(), "mitsuba_se": ms.tolist(),
                         "irradia": im.tolist(), "irradia_se": se.tolist(), "rel_diff": rel.tolist(), "z": z.tolist()})
        worst_all = max(worst_all, worst)
        report["scenes"][name] = {"regions": rows, "worst_rel_diff": worst, "worst_z": worst_z,
                                  "mitsuba_s": t_m, "irradia_s": t_i, "geometry": geo}
        print(f"{name}: {len(rows)} regions; worst |difference| {worst * 100:.2f}% of Mitsuba "
              f"(worst z {worst_z:.1f}); render time Irradia {t_i:.1f} s, Mitsuba {t_m:.1f} s "
              f"({a.seeds} x {a.spp} spp, {a.threads} threads)")
        for r in rows:
            print(f"  {r['region']:8s} {r['pixels']:5d} px  Mitsuba " +
                  " ".join(f"{v:.4f}" for v in r["mitsuba"]) + "  Irradia " +
                  " ".join(f"{v:.4f}" for v in r["irradia"]) + "  diff " +
                  " ".join(f"{v * 100:+.2f}%" for v in r["rel_diff"]) + "  z " +
                  " ".join(f"{v:+.1f}" for v in r["z"]))
    print(f"worst region difference over all scenes: {worst_all * 100:.2f}% (goal: within 1%)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(report, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
