#!/usr/bin/python3
"""Plots of an ESCM run directory (examples/escm/escm_tension): displacement profile across
the handshake at several times, with du/dX when profile.csv has it (profile.png) and the energy balance (energy.png).
Usage: /usr/bin/python3 scripts/plot_escm.py OUTDIR"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(d):
    rows = list(csv.DictReader(open(os.path.join(d, "profile.csv"))))
    times = sorted({float(r["time_s"]) for r in rows})
    grad = bool(rows) and "dux_dX" in rows[0]
    fig, axes = plt.subplots(2 if grad else 1, 1, figsize=(7, 7 if grad else 4), squeeze=False)
    ax = axes[0][0]
    for t in times:
        for src, mk in (("continuum", "-"), ("md", "o")):
            pts = sorted((float(r["x_m"]), float(r["ux_m"])) for r in rows
                         if float(r["time_s"]) == t and r["source"] == src)
            if pts:
                ax.plot([p[0] * 1e10 for p in pts], [p[1] * 1e10 for p in pts], mk,
                        ms=3, label=f"{src} {t * 1e12:.0f} ps" if src == "md" else None)
    ax.set_xlabel("x (Å)")
    ax.set_ylabel("u_x (Å)")
    ax.set_title("displacement across the handshake (lines: continuum, dots: MD cells)")
    ax.legend(fontsize=6)
    if grad:  # displacement gradient of eqs. 6.3-6.7 (D79)
        ax = axes[1][0]
        for t in times:
            for src, mk in (("continuum", "-"), ("md", "o")):
                pts = sorted((float(r["x_m"]), float(r["dux_dX"])) for r in rows
                             if float(r["time_s"]) == t and r["source"] == src)
                if pts:
                    ax.plot([p[0] * 1e10 for p in pts], [p[1] for p in pts], mk, ms=3)
        ax.set_xlabel("x (Å)")
        ax.set_ylabel("du/dX")
        ax.set_title("displacement gradient (eqs. 6.3-6.7), same frames")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "profile.png"), dpi=120)
    e = list(csv.DictReader(open(os.path.join(d, "energy.csv"))))
    t = [float(r["time_s"]) * 1e12 for r in e]
    fig, ax = plt.subplots(figsize=(7, 4))
    for k in ("cont_kinetic_J", "cont_strain_J", "md_kinetic_J", "md_potential_J",
              "work_boundary_J", "work_cont_on_md_J", "work_md_on_cont_J",
              "heat_removed_int_J", "heat_removed_ivc_J", "balance_J"):
        ax.plot(t, [float(r[k]) for r in e], label=k)
    ax.set_xlabel("t (ps)")
    ax.set_ylabel("J (slab)")
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "energy.png"), dpi=120)


if __name__ == "__main__":
    main(sys.argv[1])
