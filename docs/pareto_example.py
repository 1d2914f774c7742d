#!/usr/bin/env python3
"""A Pareto plot from a sweep run in process (docs/python.md).

Runs scenes/cube.toml with each filter mode and anisotropy limit, then plots image quality
(PSNR against the ground truth) over the texture unit's cycles and marks the Pareto front: the
settings no other setting beats in both.

    PYTHONPATH=build/python /usr/bin/python3 docs/pareto_example.py [OUT.png] [--small]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

import texsim  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "scenes", "cube.toml")


def settings(small):
    """The override sets: filter mode x anisotropy limit (smaller images with --small)."""
    size = {"output.width": 96, "output.height": 72} if small else {}
    out = []
    for mode in ("nearest", "bilinear", "trilinear"):
        for aniso in (1, 2, 4, 8):
            out.append({"materials.crate.filter.mode": mode,
                        "materials.crate.lod.max_aniso": aniso, **size})
    return out


def pareto_front(points):
    """Indices of the points with no other point at fewer-or-equal cycles and higher PSNR."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], -points[i][1]))
    front, best = [], float("-inf")
    for i in order:
        if points[i][1] > best:
            front.append(i)
            best = points[i][1]
    return front


def main(argv):
    out_png = next((a for a in argv if not a.startswith("--")), "pareto.png")
    sets = settings("--small" in argv)
    results = texsim.sweep(SCENE, sets)
    points = [(r.report["cycles"], r.report["accuracy"]["psnr_db"]) for r in results]
    labels = ["%s x%d" % (s["materials.crate.filter.mode"], s["materials.crate.lod.max_aniso"])
              for s in sets]
    front = pareto_front(points)

    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=100)
    ax.scatter([p[0] for p in points], [p[1] for p in points], label="settings", color="tab:blue")
    ax.plot([points[i][0] for i in front], [points[i][1] for i in front], color="tab:red",
            marker="o", label="Pareto front")
    for k, i in enumerate(front):  # labels alternately below and above, so neighbours stay apart
        ax.annotate(labels[i], points[i], textcoords="offset points",
                    xytext=(4, -10 if k % 2 == 0 else 5), fontsize=7)
    ax.set_xlabel("cycles (texture unit)")
    ax.set_ylabel("PSNR (dB) against the ground truth")
    ax.set_title("scenes/cube.toml: filter mode x max_aniso")
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(out_png)
    for i in front:
        print("%-14s %10d cycles %7.2f dB" % (labels[i], points[i][0], points[i][1]))
    print("wrote", out_png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
