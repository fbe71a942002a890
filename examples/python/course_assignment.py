"""A course assignment with Irradia from Python (the advanced-rendering lecture):

1. trace the ray tree of one pixel of Whitted's scene and print it;
2. render the same scene with the Whitted ray tracer and with the path tracer and
   compare them (where does the path tracer add light? indirect diffuse light);
3. solve the Cornell box by radiosity with three solvers and plot the residual per
   iteration (matplotlib if installed, else a table).

    python examples/python/course_assignment.py [--small] [--out DIR]
"""

import argparse
import os

import numpy as np

import irradia


def show_tree(node, indent=0):
    hit = node["hit"]["name"] if node.get("hit") else "-"
    cut = " (cut by %s)" % node["cut"] if node.get("cut") else ""
    print("%s%-9s depth %d hit %-10s contribution %s%s" % (
        "  " * indent, node["kind"], node["depth"], hit,
        np.round(node["contribution"], 4).tolist(), cut))
    for child in node["children"]:
        show_tree(child, indent + 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="tiny images and meshes (for tests)")
    ap.add_argument("--out", default=".", help="folder for the images and the chart")
    a = ap.parse_args()
    w, h, spp, elements = (64, 36, 8, 150) if a.small else (320, 180, 64, 1000)
    os.makedirs(a.out, exist_ok=True)

    # 1. The ray tree of the pixel in the middle of the glass sphere.
    scene = irradia.builtin("whitted")
    doc = scene.trace_pixel(w // 2, h // 2, width=w, height=h)
    print("pixel %s: radiance %s, %d rays" % (doc["pixel"], np.round(doc["radiance"], 4).tolist(), doc["rays"]))
    show_tree(doc["tree"])

    # 2. Whitted against the path tracer on the same scene and camera.
    whitted = scene.render(width=w, height=h)
    path = scene.render(width=w, height=h, integrator="path", spp=spp, progress=not a.small)
    irradia.write_image(os.path.join(a.out, "whitted.png"), whitted)
    irradia.write_image(os.path.join(a.out, "path.png"), path)
    diff = path.mean(axis=2) - whitted.mean(axis=2)
    print("mean radiance: whitted %.4f, path %.4f; path brighter on %.0f%% of the pixels"
          % (whitted.mean(), path.mean(), 100 * (diff > 0).mean()))

    # 3. Radiosity: residual per iteration of each solver on one form-factor matrix.
    r = irradia.radiosity(elements=elements, form_factors="contour", solver="gauss-seidel",
                          compare_solvers=True)
    print("%d elements; final residual %.2e; %s" % (r["radiosity"].shape[0], r["residual"], r["diagnostics"]))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        plt = None
    if plt is None:
        for name, hist in r["histories"].items():
            print("%-12s %3d iterations, residuals %s" % (name, len(hist), np.array2string(hist[:5], precision=2)))
    else:
        fig, ax = plt.subplots(figsize=(6, 4))
        for name, hist in r["histories"].items():
            ax.semilogy(np.arange(1, len(hist) + 1), hist, label=name)
        ax.set_xlabel("iteration")
        ax.set_ylabel("relative residual")
        ax.legend()
        fig.savefig(os.path.join(a.out, "residuals.png"), dpi=100)
        print("wrote", os.path.join(a.out, "residuals.png"))


if __name__ == "__main__":
    main()
