"""Writes mitsuba_layered.csv: eval and pdf of Mitsuba 3's plastic, roughplastic and
principled (and the smooth plastic's specular samples) at fixed directions, with pip Mitsuba 3 (scalar_rgb).
Run from this folder: python3 mitsuba_layered.py (needs `pip install mitsuba numpy`).

Mitsuba's `si.wi` is Irradia's `wo`, its sampled/evaluated `wo` Irradia's `wi`; its
`eval` includes the cosine |cos θ| of that direction, which is divided out here."""
import os
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
here = os.path.dirname(os.path.abspath(__file__))

RGB = lambda r, g, b: {"type": "rgb", "value": [r, g, b]}
CONFIGS = {
    "plastic_default": {"type": "plastic"},
    "plastic_linear": {"type": "plastic", "diffuse_reflectance": RGB(0.8, 0.4, 0.1),
                       "specular_reflectance": RGB(0.9, 0.9, 0.9), "int_ior": 1.6, "ext_ior": 1.1},
    "plastic_nonlinear": {"type": "plastic", "diffuse_reflectance": RGB(0.8, 0.4, 0.1),
                          "int_ior": 1.9, "ext_ior": 1.0, "nonlinear": True},
    "rp_ggx_01": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.1,
                  "diffuse_reflectance": RGB(0.7, 0.4, 0.1), "int_ior": 1.5, "ext_ior": 1.0},
    "rp_ggx_04_nonlinear": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.4,
                            "diffuse_reflectance": RGB(0.7, 0.4, 0.1), "specular_reflectance": RGB(0.8, 0.8, 0.8),
                            "int_ior": 1.49, "ext_ior": 1.000277, "nonlinear": True},
    "rp_beckmann_03": {"type": "roughplastic", "distribution": "beckmann", "alpha": 0.3,
                       "diffuse_reflectance": RGB(0.2, 0.5, 0.9), "int_ior": 1.7, "ext_ior": 1.0},
    "rp_ggx_02_all": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.2, "sample_visible": False,
                      "diffuse_reflectance": RGB(0.5, 0.5, 0.5), "int_ior": 1.5, "ext_ior": 1.0},
    "pr_default": {"type": "principled"},
    "pr_metal_aniso": {"type": "principled", "base_color": RGB(0.9, 0.6, 0.2), "roughness": 0.3,
                       "metallic": 0.8, "anisotropic": 0.5, "spec_tint": 0.4},
    "pr_sheen_cc": {"type": "principled", "base_color": RGB(0.2, 0.4, 0.8), "roughness": 0.6,
                    "sheen": 0.7, "sheen_tint": 0.5, "clearcoat": 0.8, "clearcoat_gloss": 0.6,
                    "specular": 0.3},
    "pr_glass": {"type": "principled", "base_color": RGB(0.9, 0.9, 0.7), "roughness": 0.7,
                 "spec_trans": 0.7, "eta": 1.45},
    "pr_flat": {"type": "principled", "base_color": RGB(0.6, 0.5, 0.4), "roughness": 0.8,
                "flatness": 0.6, "metallic": 0.1},
}
TWO_SIDED = {"pr_glass"}

rng = np.random.default_rng(34)


def unit(v):
    return v / np.linalg.norm(v)


def si_for(wo):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(*wo)
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    return si


ctx = mi.BSDFContext()
rows = []
for name, d in CONFIGS.items():
    b = mi.load_dict(d)
    n = 0
    while n < 12:
        wo = unit(rng.normal(size=3))
        wi = unit(rng.normal(size=3))
        if name in TWO_SIDED:
            if n < 6:
                wo[2] = abs(wo[2])
        else:
            wo[2] = abs(wo[2])
            wi[2] = abs(wi[2])
        if abs(wo[2]) < 0.05 or abs(wi[2]) < 0.05:
            continue
        si = si_for(wo)
        f = np.array(b.eval(ctx, si, mi.Vector3f(*wi))) / abs(wi[2])
        p = b.pdf(ctx, si, mi.Vector3f(*wi))
        rows.append("eval,%s,%s,%s,%.8g" % (name, ",".join("%.8g" % x for x in list(wo) + list(wi)),
                                          ",".join("%.8g" % x for x in f), p))
        n += 1
    # Transmission through the principled glass, near the refracted directions.
    if name in TWO_SIDED:
        for wo, wi in [((0.3, 0, 0.954), (-0.15, 0, -0.99)), ((0.3, 0, 0.954), (-0.4, 0.1, -0.9)),
                       ((-0.5, 0.2, 0.84), (0.3, -0.1, -0.95)), ((0.1, 0.6, 0.79), (0.0, -0.5, -0.87)),
                       ((0.2, 0.1, -0.97), (-0.3, -0.1, 0.95)), ((-0.6, 0.0, -0.8), (0.7, 0.1, 0.7))]:
            wo, wi = unit(np.array(wo, dtype=float)), unit(np.array(wi, dtype=float))
            si = si_for(wo)
            f = np.array(b.eval(ctx, si, mi.Vector3f(*wi))) / abs(wi[2])
            p = b.pdf(ctx, si, mi.Vector3f(*wi))
            rows.append("eval,%s,%s,%s,%.8g" % (name, ",".join("%.8g" % x for x in list(wo) + list(wi)),
                                              ",".join("%.8g" % x for x in f), p))
    # The smooth plastic's delta lobe: a sample with u_lobe = 0 picks it.
    if d["type"] == "plastic":
        for k in range(4):
            wo = unit(rng.normal(size=3))
            wo[2] = abs(wo[2])
            bs, w = b.sample(ctx, si_for(wo), 0.0, mi.Point2f(0.5, 0.5))
            rows.append("sample,%s,%s,%.8g,%s,%s,%.8g,%.8g" % (
                name, ",".join("%.8g" % x for x in wo), 0.0, ",".join("%.8g" % x for x in bs.wo),
                ",".join("%.8g" % x for x in np.array(w)), bs.pdf, bs.eta))

with open(os.path.join(here, "mitsuba_layered.csv"), "w") as f:
    f.write(f"# generated by mitsuba_layered.py with Mitsuba {mi.__version__} scalar_rgb\n")
    f.write("# eval,config,wo(3),wi(3),f(3),pdf | sample,config,wo(3),u_lobe,wi(3),weight(3),pdf,eta\n")
    f.write("\n".join(rows) + "\n")
