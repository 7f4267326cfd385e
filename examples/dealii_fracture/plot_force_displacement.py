#!/usr/bin/python3
"""Plot force_displacement.csv of dealii_fracture (force and dissipated energy versus the
controlled displacement). Usage: plot_force_displacement.py CSV PNG [CSV2 LABEL2 ...]
Needs matplotlib (/usr/bin/python3 on this machine has it)."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    keys = rows[0].keys()
    fk = next(k for k in keys if k.startswith("force_"))
    dk = next(k for k in keys if k.startswith("dissipated_"))
    u = [float(r["displacement_mm"]) for r in rows]
    return u, [float(r[fk]) for r in rows], [float(r[dk]) for r in rows], fk, dk


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    csvs = [(sys.argv[1], None)] + [
        (sys.argv[i], sys.argv[i + 1]) for i in range(3, len(sys.argv) - 1, 2)
    ]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for path, label in csvs:
        u, f, d, fk, dk = read(path)
        a1.plot(u, f, ".-", label=label or path)
        a2.plot(u, d, ".-", label=label or path)
    a1.set_xlabel("displacement (mm)")
    a1.set_ylabel(fk.replace("force_", "force (").replace("_", " ") + ")")
    a2.set_xlabel("displacement (mm)")
    a2.set_ylabel(dk.replace("dissipated_", "dissipated energy (").replace("_", " ") + ")")
    for a in (a1, a2):
        a.grid(alpha=0.3)
    if len(csvs) > 1:
        a1.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)
    damage_map(os.path.join(os.path.dirname(sys.argv[1]), "damage_final.csv"),
               sys.argv[2].replace(".png", "_damage.png"))
    return 0


def damage_map(path, png):
    """Cell-averaged damage (largest D_k per cell) of the last converged state, and, when the
    CSV has it, the fracture variable omega of the closure (D54) next to it."""
    if not os.path.exists(path):
        return
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return
    dk = [k for k in rows[0] if k.startswith("D")]
    x = [float(r["x_mm"]) for r in rows]
    y = [float(r["y_mm"]) for r in rows]
    h = [float(r["h_mm"]) for r in rows]
    fields = [("max_k D_k", [max(float(r[k]) for k in dk) for r in rows], None)]
    if "omega" in rows[0] and max(float(r["omega"]) for r in rows) > 0:
        fields.append(("fracture omega (D54)", [float(r["omega"]) for r in rows], (0, 1)))
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Rectangle

    fig, axes = plt.subplots(1, len(fields), figsize=(4 * len(fields), 6), squeeze=False)
    peak = {k: max(float(r[k]) for r in rows) for k in dk}
    for ax, (name, d, lim) in zip(axes[0], fields):
        # Cells are axis-aligned squares of side h on these meshes (2-D; in 3-D layers overlap).
        pc = PatchCollection(
            [Rectangle((xx - hh / 2, yy - hh / 2), hh, hh) for xx, yy, hh in zip(x, y, h)],
            cmap="inferno_r", linewidths=0, antialiased=False)
        pc.set_array(d)
        pc.set_clim(*(lim or (0, max(d) if max(d) > 0 else 1)))
        ax.add_collection(pc)
        ax.set_xlim(min(x) - h[0], max(x) + h[0])
        ax.set_ylim(min(y) - h[0], max(y) + h[0])
        ax.set_aspect("equal")
        ax.set_xlabel("x1 (mm)")
        ax.set_ylabel("x2 (mm)")
        title = name + ", last step"
        if name.startswith("max_k"):
            title += "\n" + ", ".join("max %s = %.3f" % kv for kv in peak.items())
        ax.set_title(title, fontsize=9)
        fig.colorbar(pc, ax=ax)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    sys.exit(main())
