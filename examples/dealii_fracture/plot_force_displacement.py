#!/usr/bin/python3
"""Plot force_displacement.csv of dealii_fracture (force and dissipated energy versus the
controlled displacement). Usage:

    plot_force_displacement.py [--stop TEXT] CSV PNG [CSV2 LABEL2 ...]

The force panel of the first CSV is annotated: the peak force, the first step under
dissipation (arc-length) control (column `control`) with every dissipation-controlled step
marked, and the last step with TEXT (where and why the run stopped; the program passes it;
D276).
The CSV files are SI, each column's unit at the end of its name (D317): displacement_m, force in
N/m of thickness and energy in J/m in 2-D (plane strain), N and J in 3-D; damage_final.csv has
x_m, y_m, z_m, h_m. The figures show the demo's working units, as its report does (D307, D317):
mm, N/mm and mJ/mm in 2-D, N and mJ in 3-D. Needs matplotlib (/usr/bin/python3 has it)."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The SI unit suffix of a CSV column -> the unit the figure shows and the factor from SI to it
# (D317): 1 m = 1e3 mm, 1 N/m = 1e-3 N/mm, 1 J/m = 1 mJ/mm, 1 J = 1e3 mJ.
SHOWN = {"m": ("mm", 1e3), "N_per_m": ("N/mm", 1e-3), "N": ("N", 1.0),
         "J_per_m": ("mJ/mm", 1.0), "J": ("mJ", 1e3)}


def column(path, keys, prefix):
    """The column whose name is PREFIX + an SI unit of SHOWN: (name, shown unit, factor)."""
    for k in keys:
        if k.startswith(prefix) and k[len(prefix):] in SHOWN:
            return (k,) + SHOWN[k[len(prefix):]]
    sys.exit("plot_force_displacement.py: %s: no column %s<unit> with unit one of %s (SI "
             "headers, D317); the header is %s" % (path, prefix, ", ".join(SHOWN), ",".join(keys)))


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("plot_force_displacement.py: %s: no rows" % path)
    keys = list(rows[0].keys())
    uk, _, to_mm = column(path, keys, "displacement_")
    fk, fu, to_f = column(path, keys, "force_")
    dk, du, to_d = column(path, keys, "dissipated_")
    return {
        "u": [to_mm * float(r[uk]) for r in rows],
        "f": [to_f * float(r[fk]) for r in rows],
        "d": [to_d * float(r[dk]) for r in rows],
        "control": [r.get("control", "displacement") for r in rows],
        "fu": fu,
        "du": du,
        "per_thickness": fk.endswith("_per_m"),
    }


def annotate(ax, c, stop):
    """Peak, switch to dissipation control and the stop on the force panel of one run."""
    u, f = c["u"], c["f"]
    ip = max(range(len(f)), key=lambda i: abs(f[i]))
    fu = c["fu"]
    last = len(f) - 1
    # The largest force is a peak only when the force fell after it.
    peak = ip < last
    ax.plot([u[ip]], [f[ip]], "o", color="tab:red", zorder=5,
            label="%s %.4g %s at u = %.4g mm" % ("peak" if peak else "largest force (no peak)",
                                                 f[ip], fu, u[ip]))
    text = ("peak\n%.4g %s" if peak else "%.4g %s\n(still rising)") % (f[ip], fu)
    ax.annotate(text, (u[ip], f[ip]), xytext=(0, 10),
                textcoords="offset points", ha="right", va="bottom", fontsize=8,
                color="tab:red")
    dis = [i for i, m in enumerate(c["control"]) if m == "dissipation"]
    if dis:
        ax.plot([u[i] for i in dis], [f[i] for i in dis], "s", ms=3, color="tab:orange",
                zorder=4, label="dissipation-controlled steps")
        i = dis[0]
        # Texts in the lower right corner, which a force-displacement curve leaves free.
        ax.annotate("switch to dissipation control\n(step %d, u = %.4g mm)" % (i, u[i]),
                    (u[i], f[i]), xytext=(0.97, 0.30), textcoords="axes fraction", ha="right",
                    fontsize=8, color="tab:orange",
                    bbox=dict(boxstyle="round", fc="white", ec="tab:orange", alpha=0.9), zorder=7,
                    arrowprops=dict(arrowstyle="->", color="tab:orange"))
    ax.plot([u[last]], [f[last]], "X", ms=8, color="black", zorder=6,
            label="last step (%d)" % last)
    ax.annotate(stop or "last step", (u[last], f[last]), xytext=(0.97, 0.05),
                textcoords="axes fraction", ha="right", fontsize=8, wrap=True,
                bbox=dict(boxstyle="round", fc="white", ec="0.6", alpha=0.9), zorder=7,
                arrowprops=dict(arrowstyle="->", color="black"))
    ax.set_ylim(top=max(max(f), 0) * 1.25 if max(f) > 0 else None)


def main(argv):
    stop = None
    if len(argv) > 2 and argv[1] == "--stop":
        stop = argv[2]
        argv = argv[:1] + argv[3:]
    if len(argv) < 3:
        print(__doc__)
        return 2
    csvs = [(argv[1], None)] + [(argv[i], argv[i + 1]) for i in range(3, len(argv) - 1, 2)]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.2))
    first = None
    for path, label in csvs:
        c = read(path)
        first = first or c
        a1.plot(c["u"], c["f"], ".-", label=label or os.path.basename(path), zorder=3)
        a2.plot(c["u"], c["d"], ".-", label=label or os.path.basename(path))
    annotate(a1, first, stop)
    thick = " per unit thickness" if first["per_thickness"] else ""
    a1.set_xlabel("controlled displacement (mm)")
    a1.set_ylabel("force%s (%s)" % (thick, first["fu"]))
    a1.set_title("Force–displacement", fontsize=10)
    a2.set_xlabel("controlled displacement (mm)")
    a2.set_ylabel("dissipated energy%s (%s)" % (thick, first["du"]))
    a2.set_title("Dissipated energy", fontsize=10)
    for a in (a1, a2):
        a.grid(alpha=0.3)
    # Below the axes: inside, the legend covered the peak's label when the peak sat near the
    # middle of the displacement range (the compact-tension run).
    a1.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    if len(csvs) > 1:
        a2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=120)
    damage_map(os.path.join(os.path.dirname(argv[1]), "damage_final.csv"),
               argv[2].replace(".png", "_damage.png"))
    return 0


def damage_map(path, png):
    """Cell-averaged damage (largest D_k per cell) of the last converged state, and, when the
    CSV has it, the fracture variable omega of the closure (D54) next to it; no decision codes
    in the titles (D276)."""
    if not os.path.exists(path):
        return
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return
    dk = [k for k in rows[0] if k.startswith("D")]
    keys = list(rows[0].keys())
    to_mm = [column(path, keys, c + "_")[2] for c in ("x", "y", "h")]
    x = [to_mm[0] * float(r["x_m"]) for r in rows]
    y = [to_mm[1] * float(r["y_m"]) for r in rows]
    h = [to_mm[2] * float(r["h_m"]) for r in rows]
    fields = [("max_k D_k", [max(float(r[k]) for k in dk) for r in rows], None)]
    if "omega" in rows[0] and max(float(r["omega"]) for r in rows) > 0:
        fields.append(("fracture variable ω", [float(r["omega"]) for r in rows], (0, 1)))
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
        title = name + " (dimensionless), last step"
        if name.startswith("max_k"):
            title += "\n" + ", ".join("max %s = %.3f" % kv for kv in peak.items())
        ax.set_title(title, fontsize=9)
        fig.colorbar(pc, ax=ax)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
