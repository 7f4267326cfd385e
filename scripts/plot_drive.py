#!/usr/bin/env python3
"""Plot a `pnc material drive` result: the stress-strain response of every component that
moves, stress and strain against the step, the damage state and the energy account
(external work = stored + dissipated). Input: the CSV the driver writes (SI, the unit in
each column name: stress s11_Pa, energy densities work_J_per_m3; strain e11 dimensionless;
shown in MPa and MJ/m^3). Prints 'wrote <png>'."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STRAIN = ["e11", "e22", "e33", "g23", "g13", "g12"]
STRESS = ["s11_Pa", "s22_Pa", "s33_Pa", "s23_Pa", "s13_Pa", "s12_Pa"]
ENERGY = ["work_J_per_m3", "stored_J_per_m3", "dissipated_J_per_m3"]


def read(path):
    with open(path) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    cols = {}
    for r in csv.DictReader(lines):
        for k, v in r.items():
            cols.setdefault(k, []).append(float(v))
    return cols


def moves(xs):
    return max(xs) - min(xs) > 0


def main(data, png, title):
    c = read(data)
    step = c["step"]
    fig, ax = plt.subplots(2, 2, figsize=(10, 7.5))
    a = ax[0][0]
    # a component "moves" when its stress range is not round-off of the largest one (a
    # stress-controlled zero is solved to a tolerance, not exactly)
    top = max(max(c[s]) - min(c[s]) for s in STRESS) or 1.0
    for e, s in zip(STRAIN, STRESS):
        if max(c[s]) - min(c[s]) > 1e-6 * top and moves(c[e]):
            a.plot(c[e], [v / 1e6 for v in c[s]], "-", lw=1.5, label="%s vs %s" % (s[:3], e))
    a.set_xlabel("strain (1)")
    a.set_ylabel("stress (MPa)")
    a.set_title("response", fontsize=9)
    a.grid(alpha=0.3)
    a.legend(fontsize=7)
    a = ax[0][1]
    for e in STRAIN:
        if moves(c[e]):
            a.plot(step, c[e], "-", lw=1.2, label=e)
    a.set_xlabel("step")
    a.set_ylabel("strain (1)")
    a.set_title("strain along the path", fontsize=9)
    a.grid(alpha=0.3)
    a.legend(fontsize=7)
    a = ax[1][0]
    skip = set(["step", "segment", "newton_iterations", "newton_residual_Pa"] + ENERGY + STRAIN
               + STRESS)
    for k in c:
        if k not in skip and not k.startswith("ds") and k.startswith("D"):
            a.plot(step, c[k], "-", lw=1.2, label=k)
    a.set_xlabel("step")
    a.set_ylabel("damage D (1)")
    a.set_title("damage variables", fontsize=9)
    a.grid(alpha=0.3)
    a.legend(fontsize=7)
    a = ax[1][1]
    for k, lab in zip(ENERGY, ("external work", "stored", "dissipated")):
        a.plot(step, [v / 1e6 for v in c[k]], "-", lw=1.5, label=lab)
    a.set_xlabel("step")
    a.set_ylabel("energy density (MJ/m$^3$)")
    a.set_title("energy account", fontsize=9)
    a.grid(alpha=0.3)
    a.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=100)
    os.replace(tmp, png)
    plt.close(fig)
    print("wrote " + png)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: plot_drive.py DATA.csv OUT.png TITLE")
    main(*sys.argv[1:])
