#!/usr/bin/env python3
"""Plot a rotleap run: PREFIX.energy.png (total, potential and conserved energy against time)
and, if PREFIX.rdf.csv exists, PREFIX.rdf.png (the site-site RDFs).  usage: plot.py PREFIX"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def columns(path):
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    head, data = rows[0], rows[1:]
    return {h: [float(r[i]) for r in data] for i, h in enumerate(head)}


def main(prefix):
    t = columns(prefix + ".thermo.csv")
    fig, ax = plt.subplots(figsize=(7, 4))
    for key, label in (("total", "total"), ("potential", "potential"), ("conserved", "conserved")):
        ax.plot(t["time"], t[key], label=label)
    ax.set_xlabel("time (ps)")
    ax.set_ylabel("energy (kJ/mol)")
    ax.legend()
    ax.set_title(prefix + ": energy trace")
    fig.tight_layout()
    fig.savefig(prefix + ".energy.png", dpi=120)
    print("wrote", prefix + ".energy.png")
    try:
        g = columns(prefix + ".rdf.csv")
    except FileNotFoundError:
        return
    fig, ax = plt.subplots(figsize=(7, 4))
    rkey = next(k for k in g if k.startswith("r_"))  # r_nm (real) or r_sigma (lj)
    for key in g:
        if key != rkey:
            ax.plot(g[rkey], g[key], label=key[2:])
    ax.axhline(1.0, color="grey", lw=0.5)
    ax.set_xlabel("r (nm)" if rkey == "r_nm" else "r (sigma)")
    ax.set_ylabel("g(r)")
    ax.legend()
    ax.set_title(prefix + ": radial distribution functions")
    fig.tight_layout()
    fig.savefig(prefix + ".rdf.png", dpi=120)
    print("wrote", prefix + ".rdf.png")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: plot.py PREFIX")
    main(sys.argv[1])
