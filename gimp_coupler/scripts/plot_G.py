#!/usr/bin/python3
"""Energy release rates of a pnc gimp run: plot_G.py HISTORY.csv OUT.png [TITLE].

Reads the crack-tip columns of history.csv (J_<tip>, GI_<tip>, GII_<tip> in J/m^2,
length_<tip> in m; <tip> = <crack>_start or <crack>_end) and draws, per tip, J, G_I and G_II
against crack length (left) and against time (right). Needs matplotlib (/usr/bin/python3 on
the project machine).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: plot_G.py HISTORY.csv OUT.png [TITLE]")
    with open(sys.argv[1]) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    reader = csv.DictReader(lines)
    rows = [{k: float(v) for k, v in r.items()} for r in reader]
    if not rows:
        sys.exit("no rows in " + sys.argv[1])
    tips = [k[2:] for k in rows[0] if k.startswith("J_")]
    if not tips:
        sys.exit("no crack-tip columns (J_<tip>) in " + sys.argv[1])
    t = [r["time"] for r in rows]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for tip in tips:
        a = [r["length_" + tip] for r in rows]
        for key, ls in (("J_", "-"), ("GI_", "--"), ("GII_", ":")):
            g = [r[key + tip] for r in rows]
            ok = [i for i, v in enumerate(g) if not math.isnan(v)]
            lab = {"J_": "J = G", "GI_": "G_I", "GII_": "G_II"}[key] + " " + tip
            ax1.plot([a[i] for i in ok], [g[i] for i in ok], ls=ls, marker="." if key == "J_" else None,
                     label=lab)
            ax2.plot([t[i] for i in ok], [g[i] for i in ok], ls=ls, label=lab)
    ax1.set_xlabel("crack length (m)")
    ax2.set_xlabel("time (s)")
    for ax in (ax1, ax2):
        ax.set_ylabel("energy release rate (J/m$^2$)")
        ax.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle(sys.argv[3] if len(sys.argv) > 3 else "energy release rate")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()
