#!/usr/bin/python3
"""Plots of an ESCM run directory (examples/escm/escm_tension): displacement profile across
the handshake at several times, with its gradient when profile.csv has it (profile.png), the
energy balance (energy.png) and, for the crack cases II/III (crack.csv), the continuum crack tip
and the atomistic separation against time and the continuum tip's J, G_I, G_II (J/m^2) with
the critical Gc of summary.json and a marker where growth stopped, and why (crack.png; D272).
Usage: /usr/bin/python3 scripts/plot_escm.py OUTDIR"""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(d):
    rows = list(csv.DictReader(open(os.path.join(d, "profile.csv"))))
    times = sorted({float(r["time_s"]) for r in rows})
    cols = list(rows[0].keys()) if rows else ["time_s", "x_m", "ux_m", "source"]
    ucol = cols[2]  # ux_m (Case I, III) or uy_m (Case II)
    gcol = cols[4] if len(cols) > 4 else None  # dux_dX, duy_dY or dux_dY
    grad = gcol is not None
    fig, axes = plt.subplots(2 if grad else 1, 1, figsize=(7, 7 if grad else 4), squeeze=False)
    ax = axes[0][0]
    for t in times:
        for src, mk in (("continuum", "-"), ("md", "o")):
            pts = sorted((float(r["x_m"]), float(r[ucol])) for r in rows
                         if float(r["time_s"]) == t and r["source"] == src)
            if pts:
                ax.plot([p[0] * 1e10 for p in pts], [p[1] * 1e10 for p in pts], mk,
                        ms=3, label=f"{src} {t * 1e12:.0f} ps" if src == "md" else None)
    ax.set_xlabel("x (Å)")
    ax.set_ylabel(ucol.replace("_m", "").replace("u", "u_", 1) + " (Å)")
    ax.set_title("displacement across the handshake (lines: continuum, dots: MD cells)")
    ax.legend(fontsize=6)
    if grad:  # displacement gradient of docs/theory.md §6.3 (D79)
        ax = axes[1][0]
        for t in times:
            for src, mk in (("continuum", "-"), ("md", "o")):
                pts = sorted((float(r["x_m"]), float(r[gcol])) for r in rows
                             if float(r["time_s"]) == t and r["source"] == src)
                if pts:
                    ax.plot([p[0] * 1e10 for p in pts], [p[1] for p in pts], mk, ms=3)
        ax.set_xlabel("x (Å)")
        ax.set_ylabel(gcol.replace("_", "/"))
        ax.set_title("displacement gradient (theory.md §6.3), same frames")
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
    if os.path.exists(os.path.join(d, "crack.csv")):
        plot_crack(d)


def plot_crack(d):
    """Cases II/III: continuum tip and atomistic separation against time (crack.png)."""
    c = list(csv.DictReader(open(os.path.join(d, "crack.csv"))))
    t = [float(r["time_s"]) * 1e12 for r in c]
    fig, axes = plt.subplots(4, 1, figsize=(7, 10.5), sharex=True)
    ax = axes[0]
    ax.plot(t, [float(r["tip_x_m"]) * 1e10 for r in c], label="continuum tip x")
    x0 = float(c[0]["tip_x_m"]) - float(c[0]["crack_length_m"]) if c else 0.0
    ax.plot(t, [(x0 + float(r["crack_length_m"])) * 1e10 for r in c], ":", lw=0.8)
    ax.set_ylabel("x (Å)")
    ax.legend(fontsize=7)
    ax = axes[1]
    ax.plot(t, [float(r["md_broken_bonds"]) for r in c], label="broken bonds across the line")
    ax.plot(t, [float(r["md_crack_length_m"]) * 1e10 for r in c],
            label="separated length in the MD region (Å)")
    ax.legend(fontsize=7)
    ax = axes[2]
    for k, lab in (("opening_m", "continuum opening behind the tip"),
                   ("sliding_m", "continuum sliding behind the tip"),
                   ("md_entry_opening_m", "MD opening, entry column"),
                   ("md_entry_sliding_m", "MD sliding, entry column")):
        ax.plot(t, [float(r[k]) * 1e10 for r in c], label=lab)
    ax.set_ylabel("Å")
    ax.legend(fontsize=7)
    ax = axes[3]
    for k, lab, ls in (("J_J_per_m2", "J = G", "-"), ("GI_J_per_m2", "G_I", "--"),
                       ("GII_J_per_m2", "G_II", ":")):
        ax.plot(t, [float(r[k]) for r in c], ls=ls, label=lab)
    crack_marks(d, c, t, ax)
    ax.set_ylabel("J/m$^2$")
    ax.set_xlabel("t (ps)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "crack.png"), dpi=120)


def crack_marks(d, c, t, ax):
    """The critical Gc (dash-dotted) and a marker at the last increment, labelled with why the
    continuum crack stopped growing (summary.json "crack")."""
    try:
        with open(os.path.join(d, "summary.json")) as f:
            cj = json.load(f).get("crack", {})
    except (OSError, ValueError):
        return
    gc = cj.get("Gc_J_per_m2")
    if gc:
        ax.axhline(gc, color="black", lw=1.2, ls="-.", label=f"G_c = {gc:.4g} J/m$^2$")
    if not c:
        return
    inc = [float(r["increments"]) for r in c]
    i = len(inc) - 1
    for k in range(len(inc) - 1, 0, -1):
        if inc[k] != inc[k - 1]:
            i = k
            break
    n = cj.get("max_increments")
    if n is not None and inc[i] >= n:
        why = f"max_increments ({n}) reached"
    elif gc and float(c[-1]["J_J_per_m2"]) < gc:
        why = "J < G_c at the end"
    else:
        why = "still growing"
    ax.plot([t[i]], [float(c[i]["J_J_per_m2"])], marker="X", ms=10, color="crimson", ls="none",
            label="growth stopped: " + why)


if __name__ == "__main__":
    main(sys.argv[1])
