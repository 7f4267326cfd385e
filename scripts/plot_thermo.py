#!/usr/bin/env python3
"""Plots of `pnc thermo` (matplotlib). Units: kcal/mol, A, fs as in the CSV headers.

usage: plot_thermo.py ti DHDL_CSV DA_CSV OUTDIR
       plot_thermo.py persistence RATES_CSV OUTDIR
       plot_thermo.py work WORK_CSV OUTDIR          (work.csv of `pnc thermo work`, SI)
Prints "wrote <png>" per figure.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


JOULE_PER_KCAL_MOL = 4184.0 / 6.02214076e23  # J per kcal/mol (one box's energy)


def kcal_mol(v):
    """A CSV energy in J, as kcal/mol for the axes (the LAMMPS real unit the runs used)."""
    return float(v) / JOULE_PER_KCAL_MOL


def ti(dhdl_csv, da_csv, out):
    rows = read(dhdl_csv)
    states = []
    for r in rows:
        if r["state"] not in states:
            states.append(r["state"])
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for s in states:
        rr = [r for r in rows if r["state"] == s]
        ax.errorbar([float(r["lambda"]) for r in rr], [kcal_mol(r["dhdl_J"]) for r in rr],
                    yerr=[kcal_mol(r["dhdl_se_J"]) for r in rr], marker="o", capsize=3, label=s)
    ax.set_xlabel("lambda")
    ax.set_ylabel("<dH/dlambda> (kcal/mol)")
    ax.set_title("TI integrand per deformation state (error bars: 1 s.e.)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    p = os.path.join(out, "dhdl_vs_lambda.png")
    fig.savefig(p, dpi=120)
    print("wrote " + p)
    rows = read(da_csv)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, kind, lab in ((axes[0], "vol", "volumetric strain tr(eps) = 3 alpha"),
                          (axes[1], "dev", "deviatoric strain eps12 = eps13 = eps23 = beta")):
        rr = [r for r in rows if r["kind"] == kind]
        if not rr:
            ax.set_visible(False)
            continue
        x = [float(r["strain_measure"]) for r in rr]
        ax.errorbar(x, [kcal_mol(r["dA_J"]) for r in rr], yerr=[kcal_mol(r["dA_se_J"]) for r in rr],
                    marker="o", capsize=3, ls="-")
        ax.set_xlabel(lab)
        ax.set_ylabel("Delta A = A(lambda=1) - A(lambda=0) (kcal/mol)")
        ax.set_title("free energy vs volumetric strain" if kind == "vol"
                     else "free energy vs deviatoric strain")
    fig.tight_layout()
    p = os.path.join(out, "dA_vs_strain.png")
    fig.savefig(p, dpi=120)
    print("wrote " + p)


def persistence(rates_csv, out):
    rows = read(rates_csv)
    x = [float(r["rate_m_per_s"]) for r in rows if r["kind"] == "rate"]
    y = [float(r["EI_N_m2"]) for r in rows if r["kind"] == "rate"]
    e = [float(r["EI_err_N_m2"]) for r in rows if r["kind"] == "rate"]
    ye = [float(r["EI_end_N_m2"]) for r in rows if r["kind"] == "rate"]
    fit = [r for r in rows if r["kind"] == "fit"][0]
    c0, c1, ci = float(fit["EI_N_m2"]), float(fit["EI_end_N_m2"]), float(fit["EI_err_N_m2"])
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.errorbar(x, y, yerr=e, marker="o", ls="none", capsize=3, label="EI = L^3/48 dF/dd")
    ax.plot(x, ye, "s", mfc="none", label="EI = F L^3/(48 d), end of pull (theory.md §4.5)")
    xs = [0.0, max(x) * 1.05]
    ax.plot(xs, [c0 + c1 * v for v in xs], "-", label="linear fit, extrapolated")
    ax.errorbar([0.0], [c0], yerr=[ci], marker="D", color="k", capsize=4, label="EI(0), 95 % CI")
    ax.set_xlabel("pulling rate (m/s)")
    ax.set_ylabel("EI (N m^2)")
    ax.set_title("bending stiffness vs pulling rate")
    ax.legend(fontsize=8)
    fig.tight_layout()
    p = os.path.join(out, "EI_vs_rate.png")
    fig.savefig(p, dpi=120)
    print("wrote " + p)


def work(work_csv, out):
    """da per case against the largest strain component of each point: error bars 1 s.e.
    (independent points), the band +-2 x the any-correlation bound (below it: noise, D143);
    with two temperatures a second panel holds the entropic and energetic parts."""
    rows = read(work_csv)
    split = rows and "da_entropic_J_per_m3" in rows[0]
    cases = []
    for r in rows:
        if r["case"] not in cases:
            cases.append(r["case"])
    fig, axes = plt.subplots(1, 2 if split else 1, figsize=(11 if split else 6.4, 4.4),
                             squeeze=False)
    comps = ["e11_1", "e22_1", "e33_1", "g23_1", "g13_1", "g12_1"]
    for c in cases:
        rr = [r for r in rows if r["case"] == c]
        x = [max(abs(float(r[k])) for k in comps) for r in rr]
        y = [float(r["da_J_per_m3"]) / 1e6 for r in rr]
        e = [float(r["da_stderr_indep_J_per_m3"]) / 1e6 for r in rr]
        b = [2 * float(r["da_stderr_bound_J_per_m3"]) / 1e6 for r in rr]
        line = axes[0][0].errorbar(x, y, yerr=e, marker="o", ms=3, capsize=2, label="case " + c)
        axes[0][0].fill_between(x, [-v for v in b], b, color=line[0].get_color(), alpha=0.12)
        if split:
            for key, ls in (("da_entropic_J_per_m3", "--"), ("da_energetic_J_per_m3", ":")):
                axes[0][1].plot(x, [float(r[key]) / 1e6 for r in rr], ls, marker=".",
                                label="case %s, %s" % (c, key.split("_")[1]))
    panels = [(axes[0][0], "free energy density da = integral of sigma de (MJ/m^3)",
               "stress work per case (bars 1 s.e.; band: 2 x error bound)")]
    if split:
        panels.append((axes[0][1], "da part (MJ/m^3)", "entropic (-T ds) and energetic (du) parts"))
    for a, ylabel, title in panels:
        a.axhline(0, color="0.5", lw=0.8)
        a.set_xlabel("largest strain component |e_ij| (1)")
        a.set_ylabel(ylabel)
        a.set_title(title, fontsize=10)
        a.legend(fontsize=7)
    fig.tight_layout()
    p = os.path.join(out, "work.png")
    fig.savefig(p, dpi=120)
    print("wrote " + p)


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "ti":
        ti(sys.argv[2], sys.argv[3], sys.argv[4])
    elif len(sys.argv) == 4 and sys.argv[1] == "persistence":
        persistence(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "work":
        work(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
