#!/usr/bin/python3
"""Energy balance of a pnc gimp run: plot_energy.py HISTORY.csv OUT.png [TITLE] [--per-thickness].

Reads history.csv (the unit ends each column name, D335: time_s; energies kinetic_J, ...
in 3-D, kinetic_J_per_m, ... per metre of thickness in 2-D, which labels the axis J/m;
--per-thickness is accepted, the names decide) and draws kinetic, strain, external work,
boundary work, damping work (if present) and the energy error
KE + SE - E0 - W_ext - W_bc - W_damp against time. Needs matplotlib
(/usr/bin/python3 on the project machine).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    per_thickness = "--per-thickness" in sys.argv[1:]
    args = [a for a in sys.argv[1:] if a != "--per-thickness"]
    if len(args) < 2:
        sys.exit("usage: plot_energy.py HISTORY.csv OUT.png [TITLE] [--per-thickness]")
    rows = []
    with open(args[0]) as f:
        lines = [ln for ln in f if not ln.startswith("#")]
    reader = csv.DictReader(lines)
    for r in reader:
        rows.append({k: float(v) for k, v in r.items()})
    if not rows:
        sys.exit("no rows in " + args[0])
    # the energy unit from the names (D335): J/m in 2-D, J in 3-D
    unit = next((u for u in ("_J_per_m", "_J") if "kinetic" + u in rows[0]), None)
    if unit is None:
        sys.exit("no kinetic_J_per_m or kinetic_J column in " + args[0])
    per_thickness = unit == "_J_per_m"
    t = [r["time_s"] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for key, label in [("kinetic", "kinetic"), ("strain", "strain energy"),
                       ("external_work", "external work"), ("boundary_work", "boundary work"),
                       ("damping_work", "damping work"),
                       ("balance", "error: KE + SE - E0 - W_ext - W_bc - W_damp")]:
        if key + unit not in rows[0]:  # histories written before damping existed
            continue
        ax.plot(t, [r[key + unit] for r in rows], label=label,
                lw=1.5 if key != "balance" else 2.0, ls="-" if key != "balance" else "--")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy per unit thickness (J/m)" if per_thickness else "energy (J)")
    ax.set_title(args[2] if len(args) > 2 else "energy balance")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args[1], dpi=120)


if __name__ == "__main__":
    main()
