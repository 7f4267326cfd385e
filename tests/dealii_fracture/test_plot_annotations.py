#!/usr/bin/python3
"""The annotations of the deal.II demo's force-displacement figure (D276).

    /usr/bin/python3 test_plot_annotations.py EXAMPLE_DIR   # examples/dealii_fracture

Writes two small force_displacement.csv files in SI (D317) in a fresh temporary directory (a
run through its peak with dissipation-controlled steps from step 4, and a run whose force still
rises at the end), draws them with EXAMPLE_DIR/plot_force_displacement.py and checks the
figure, drawn in mm and N/mm (D317): the peak is marked with the largest force of the CSV, the
first dissipation-controlled step is pointed at, the last step carries the --stop text, the
axis labels carry the units per unit thickness, and no title or label holds a decision-record
code (D followed by two or more digits). A CSV with the old millimetre header is refused
naming the file. Exit code 0 when all holds. Needs matplotlib (/usr/bin/python3 has it).
"""
import importlib.util
import os
import re
import shutil
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The demo's SI header of a 2-D run; the figure shows mm and N/mm (D317).
HEAD = ("step,displacement_m,force_N_per_m,external_work_J_per_m,elastic_energy_J_per_m,"
        "dissipated_J_per_m,work_minus_elastic_J_per_m,max_damage,max_fracture,"
        "newton_iterations,cuts,dofs,control\n")


def write(path, rows, head=HEAD):
    """ROWS of (u in mm, F in N/mm, control) written in SI: 1 mm = 1e-3 m, 1 N/mm = 1e3 N/m."""
    with open(path, "w") as f:
        f.write(head)
        for i, (u, F, mode) in enumerate(rows):
            f.write("%d,%.10g,%.10g,0,0,%g,0,0,0,1,0,100,%s\n" % (i, 1e-3 * u, 1e3 * F, 0.1 * i,
                                                                 mode))


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    spec = importlib.util.spec_from_file_location(
        "plot_fd", os.path.join(sys.argv[1], "plot_force_displacement.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    fails = []
    work = tempfile.mkdtemp(prefix="pnc_dealii_plot_")
    try:
        # through the peak (step 5, 200 N/mm), dissipation control from step 4
        d = "displacement"
        peak_rows = [(0, 0, d), (0.1, 50, d), (0.2, 100, d), (0.3, 150, d),
                     (0.35, 180, "dissipation"), (0.4, 200, "dissipation"),
                     (0.38, 120, "dissipation"), (0.3, 15, "dissipation")]
        csv1 = os.path.join(work, "force_displacement.csv")
        write(csv1, peak_rows)
        stop = "stop: force below 10 % of the peak (step 7, u = 0.3 mm)"
        if mod.main(["plot", "--stop", stop, csv1, os.path.join(work, "fd.png")]) != 0:
            fails.append("the plot script failed")
        fig = plt.figure(plt.get_fignums()[0])
        ax = fig.axes[0]
        texts = [t.get_text() for t in ax.texts]
        if "peak\n200 N/mm" not in texts:
            fails.append("peak 200 N/mm not annotated: %s" % texts)
        if not any(t.startswith("switch to dissipation control\n(step 4, u = 0.35 mm)")
                   for t in texts):
            fails.append("switch at step 4 not annotated: %s" % texts)
        if stop not in texts:
            fails.append("stop text not on the figure: %s" % texts)
        if ax.get_ylabel() != "force per unit thickness (N/mm)":
            fails.append("force label %r" % ax.get_ylabel())
        if fig.axes[1].get_ylabel() != "dissipated energy per unit thickness (mJ/mm)":
            fails.append("energy label %r" % fig.axes[1].get_ylabel())
        words = [a.get_title() for a in fig.axes] + [a.get_xlabel() for a in fig.axes] + texts
        words += [a.get_ylabel() for a in fig.axes]
        words += [t.get_text() for t in ax.get_legend().get_texts()]
        if any(re.search(r"\bD\d{2,}\b", w) for w in words):
            fails.append("a decision code in the figure: %s" % words)
        plt.close("all")
        # still rising at the end: no peak claimed, no switch
        write(csv1, [(0, 0, d), (0.1, 50, d), (0.2, 90, d)])
        mod.main(["plot", csv1, os.path.join(work, "fd2.png")])
        texts = [t.get_text() for t in plt.figure(plt.get_fignums()[0]).axes[0].texts]
        if "90 N/mm\n(still rising)" not in texts or any(t.startswith("peak") for t in texts):
            fails.append("a rising curve must not claim a peak: %s" % texts)
        if any(t.startswith("switch") for t in texts):
            fails.append("no switch without dissipation control: %s" % texts)
        plt.close("all")
        # a CSV with the old millimetre header is refused, naming the file and the column
        write(csv1, [(0, 0, d), (0.1, 50, d)], HEAD.replace("_m,", "_mm,"))
        try:
            mod.main(["plot", csv1, os.path.join(work, "fd3.png")])
            fails.append("a CSV with displacement_mm was plotted")
        except SystemExit as e:
            if csv1 not in str(e) or "displacement_" not in str(e):
                fails.append("the refusal names the file and the column: %s" % e)
    finally:
        shutil.rmtree(work)
    for f in fails:
        print("FAIL:", f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
