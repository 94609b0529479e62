#!/usr/bin/env python3
"""Plots of a `rotleap scan`: PREFIX.scan_calE.png (calE against run length, one panel per time
step, one curve per integrator, like Fig. 1 of Omelyan's paper) and PREFIX.scan_pareto.png (cost
against accuracy: wall time per simulated unit against calE/calU, with each integrator's Pareto
front).  Each PNG is written to a temporary name and renamed.  usage: plot_scan.py PREFIX"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, path)
    plt.close(fig)


def main(prefix):
    runs = rows(prefix + ".scan.csv")
    curve = rows(prefix + ".scan_calE.csv")
    hkey = [k for k in runs[0] if k.startswith("h_")][0]
    unit = "fs" if hkey == "h_fs" else "reduced"
    tkey = [k for k in curve[0] if k.startswith("time_")][0]
    integrators = list(dict.fromkeys(r["integrator"] for r in runs))
    steps = sorted({float(r[hkey]) for r in runs})
    colours = {name: "C%d" % i for i, name in enumerate(integrators)}

    ncol = min(3, len(steps))
    nrow = (len(steps) + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.3 * nrow), squeeze=False)
    for ax, h in zip(axes.flat, steps):
        for name in integrators:
            pts = [(float(c[tkey]), float(c["calE"])) for c in curve
                   if c["integrator"] == name and float(c[hkey]) == h and float(c["calE"]) > 0]
            if pts:
                ax.plot([p[0] for p in pts], [100 * p[1] for p in pts], color=colours[name], label=name)
        ax.set_yscale("log")
        ax.set_title("h = %g %s" % (h, unit))
        ax.set_xlabel("run length (%s)" % ("ps" if unit == "fs" else "reduced"))
        ax.set_ylabel("calE (%)")
    for ax in list(axes.flat)[len(steps):]:
        ax.axis("off")
    axes.flat[0].legend(fontsize=8)
    fig.suptitle("total-energy fluctuation against run length: " + os.path.basename(prefix))
    fig.tight_layout()
    save(fig, prefix + ".scan_calE.png")

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for name in integrators:
        pts = []
        for r in runs:
            if r["integrator"] != name or r["status"] != "ok" or float(r["calU"]) <= 0:
                continue
            h = float(r[hkey])
            cost = float(r["wall_s_per_step"]) / h  # seconds per simulated fs (or reduced unit)
            pts.append((cost, 100 * float(r["calE_over_calU"]), h))
        if not pts:
            continue
        pts.sort()
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], color=colours[name], label=name)
        for c, a, h in pts:
            ax.annotate("%g" % h, (c, a), fontsize=7, xytext=(3, 3), textcoords="offset points")
        front, best = [], float("inf")  # cheapest-first: keep the points that improve accuracy
        for c, a, h in pts:
            if a < best:
                front.append((c, a))
                best = a
        ax.plot([p[0] for p in front], [p[1] for p in front], color=colours[name], lw=1)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall seconds per simulated %s" % ("fs" if unit == "fs" else "time unit"))
    ax.set_ylabel("calE / calU (%)")
    ax.set_title("cost against accuracy (labels: h in %s)" % unit)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, prefix + ".scan_pareto.png")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
