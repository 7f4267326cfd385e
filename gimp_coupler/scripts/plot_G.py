#!/usr/bin/python3
"""Energy release rates of a pnc gimp run:
plot_G.py HISTORY.csv OUT.png [TITLE] [--gc CRACK GC]... [--stop CRACK REASON]...

Reads the crack-tip columns of history.csv (J_<tip>_J_per_m2, GI_<tip>_J_per_m2,
GII_<tip>_J_per_m2, length_<tip>_m, time_s; the unit ends each name, D335; <tip> =
<crack>_start, <crack>_end or <crack>_front<k>) and draws, per tip, J, G_I and G_II
against crack length (left) and against time (right). `--gc CRACK GC` draws the critical
energy release rate of that crack (J/m^2) as a horizontal line; `--stop CRACK REASON` marks
where its tips last grew (the last change of length_<tip>; the end of the run when it never
grew) and labels the marker with why growth stopped (e.g. "max_increments (12) reached"; D272).
Needs matplotlib (/usr/bin/python3 on the project machine).
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def parse(argv):
    """Positional arguments and the --gc / --stop pairs (crack name -> value)."""
    pos, gc, stop = [], {}, {}
    i = 0
    while i < len(argv):
        if argv[i] in ("--gc", "--stop"):
            if i + 2 >= len(argv):
                sys.exit(argv[i] + " needs CRACK and a value")
            if argv[i] == "--gc":
                gc[argv[i + 1]] = float(argv[i + 2])
            else:
                stop[argv[i + 1]] = argv[i + 2]
            i += 3
        else:
            pos.append(argv[i])
            i += 1
    return pos, gc, stop


def crack_of(tip, names):
    """The crack of a tip column suffix <crack>_start / <crack>_end / <crack>_front<k>."""
    for n in names:
        if tip.startswith(n + "_"):
            return n
    return None


def last_growth(a, g):
    """Index of the row where the crack length last changed (the end when it never did),
    moved back to a row with a finite G."""
    i = len(a) - 1
    for k in range(len(a) - 1, 0, -1):
        if a[k] != a[k - 1]:
            i = k
            break
    while i > 0 and math.isnan(g[i]):
        i -= 1
    return i


def main():
    pos, gc, stop = parse(sys.argv[1:])
    if len(pos) < 2:
        sys.exit("usage: plot_G.py HISTORY.csv OUT.png [TITLE] [--gc CRACK GC] "
                 "[--stop CRACK REASON]")
    with open(pos[0]) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    reader = csv.DictReader(lines)
    rows = [{k: float(v) for k, v in r.items()} for r in reader]
    if not rows:
        sys.exit("no rows in " + pos[0])
    G, L = "_J_per_m2", "_m"  # the unit suffixes of G and of lengths
    tips = [k[2:-len(G)] for k in rows[0] if k.startswith("J_") and k.endswith(G)]
    if not tips:
        sys.exit("no crack-tip columns (J_<tip>" + G + ") in " + pos[0])
    t = [r["time_s"] for r in rows]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for tip in tips:
        a = [r["length_" + tip + L] for r in rows]
        for key, ls in (("J_", "-"), ("GI_", "--"), ("GII_", ":")):
            g = [r[key + tip + G] for r in rows]
            ok = [i for i, v in enumerate(g) if not math.isnan(v)]
            lab = {"J_": "J = G", "GI_": "G_I", "GII_": "G_II"}[key] + " " + tip
            ax1.plot([a[i] for i in ok], [g[i] for i in ok], ls=ls, marker="." if key == "J_" else None,
                     label=lab)
            ax2.plot([t[i] for i in ok], [g[i] for i in ok], ls=ls, label=lab)
        crack = crack_of(tip, stop)
        if crack is not None:
            j = [r["J_" + tip + G] for r in rows]
            i = last_growth(a, j)
            if not math.isnan(j[i]):
                for ax, x in ((ax1, a[i]), (ax2, t[i])):
                    ax.plot([x], [j[i]], marker="X", ms=11, color="crimson", ls="none",
                            label="growth stopped: " + stop[crack] if ax is ax2 else None)
                ax1.annotate("stopped: " + stop[crack], (a[i], j[i]), textcoords="offset points",
                             xytext=(-8, 10), ha="right", fontsize=8, color="crimson")
    for n, v in gc.items():
        for ax in (ax1, ax2):
            ax.axhline(v, color="black", lw=1.2, ls="-.",
                       label=f"G_c {n} = {v:.4g} J/m$^2$" if ax is ax2 else None)
    ax1.set_xlabel("crack length (m)")
    ax2.set_xlabel("time (s)")
    for ax in (ax1, ax2):
        ax.set_ylabel("energy release rate (J/m$^2$)")
        ax.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle(pos[2] if len(pos) > 2 else "energy release rate")
    fig.tight_layout()
    fig.savefig(pos[1], dpi=120)


if __name__ == "__main__":
    main()
