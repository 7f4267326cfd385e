#!/usr/bin/env python3
"""Plot NDM fits: one PNG per deformation case, each active stress component against the
driven strain (data as points, the fitted NDM as a line), like figures 6.22-6.41 of Nair
(2010). Input: the curves.csv written by `pnc fit` (stress in MPa). Prints 'wrote <png>'."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COMP = ["11", "22", "33", "23", "13", "12"]
CASE = {1: ("extension x1", "\\varepsilon_{11}"), 2: ("extension x2", "\\varepsilon_{22}"),
        3: ("extension x3", "\\varepsilon_{33}"), 4: ("simple shear 2-3", "\\gamma_{23}"),
        5: ("simple shear 1-3", "\\gamma_{13}"), 6: ("simple shear 1-2", "\\gamma_{12}")}


def main(curves, outdir, title):
    rows = {}
    with open(curves) as f:
        for r in csv.DictReader(f):
            key = (int(r["case"]), int(r["component"]))
            rows.setdefault(key, {"data": ([], []), "model": ([], [])})
            d = rows[key][r["kind"]]
            d[0].append(float(r["strain"]))
            d[1].append(float(r["stress_mpa"]))
    cases = sorted({c for c, _ in rows})
    for c in cases:
        comps = sorted(k for cc, k in rows if cc == c)
        fig, axes = plt.subplots(1, len(comps), figsize=(4.2 * len(comps), 3.6), squeeze=False)
        name, xlab = CASE[c]
        for ax, k in zip(axes[0], comps):
            d = rows[(c, k)]
            ax.plot(d["data"][0], d["data"][1], "o", ms=2.5, alpha=0.6, label="data")
            ax.plot(d["model"][0], d["model"][1], "-", lw=2, label="NDM fit")
            ax.set_xlabel("$%s$" % xlab)
            ax.set_ylabel("$\\sigma_{%s}$ (MPa)" % COMP[k])
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        fig.suptitle("%s - case %d: %s" % (title, c, name), fontsize=10)
        fig.tight_layout()
        png = os.path.join(outdir, "case%d.png" % c)
        fig.savefig(png + ".tmp.png", dpi=110)
        os.replace(png + ".tmp.png", png)
        plt.close(fig)
        print("wrote " + png)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: plot_fit.py CURVES.csv OUTDIR TITLE")
    main(*sys.argv[1:])
