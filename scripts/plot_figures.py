#!/usr/bin/env python3
"""Draw every figure of one pnc run in one process (matplotlib start-up paid once).

Input: the JSON job list written by pnc (app/figures.hpp, "pnc figure jobs v1"):
  {"figures": [{"png", "title", "columns", "panels": [
      {"title", "xlabel", "ylabel", "fit_limit"?,
       "series": [{"style": "points"|"line"|"line_points", "label", "x", "y", "yerr"?,
                   "colour", "width"?}],
       "residual"?: {same as a series}, "residual_label"?}]}]}
Numbers are plotted as given (units are in the labels; null is a gap). Prints 'wrote <png>'
per figure; each PNG is written to a fresh temporary file and renamed into place.

--describe OUT.json: also writes what was drawn, read back from the matplotlib artists (for
tests of a figure's content): {"figures": [{"png", "title", "axes": [{"title", "xlabel",
"ylabel", "lines": [{"label", "points"}], "error_bars": [segments of each error-bar set]}]}]}."""
import json
import math
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
# Styling through rcParams, not per-axes calls: matplotlib's cost is per tick and per call,
# and a run figure has tens of axes. Labels are plain text (no TeX parsing).
matplotlib.rcParams.update({
    "text.parse_math": False, "axes.grid": True, "grid.alpha": 0.3, "grid.linewidth": 0.5,
    "axes.titlesize": 9, "axes.labelsize": 8.5, "xtick.labelsize": 7.5,
    "ytick.labelsize": 7.5, "legend.fontsize": 7, "legend.framealpha": 0.8,
    "axes.xmargin": 0.03})
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

PALETTE = plt.get_cmap("tab10").colors
PANEL_W, PANEL_H, RESID_H = 3.5, 2.35, 0.85  # inches


def finite(xs, ys, es=None):
    out = [(x, y, e) for x, y, e in zip(xs, ys, es or [0.0] * len(xs))
           if x is not None and y is not None]
    return ([o[0] for o in out], [o[1] for o in out],
            [o[2] if o[2] is not None else 0.0 for o in out])


def draw_series(ax, s, colour):
    x, y, e = finite(s["x"], s["y"], s.get("yerr"))
    label = s["label"] or None
    if s["style"] == "line":
        ax.plot(x, y, "-", lw=s.get("width", 1.8), color=colour, label=label, zorder=3)
        return
    if "yerr" in s:  # one LineCollection: much cheaper than Axes.errorbar
        ax.add_collection(LineCollection(
            [((xi, yi - ei), (xi, yi + ei)) for xi, yi, ei in zip(x, y, e)],
            colors=[colour], linewidths=0.7, alpha=0.6, zorder=2))
    joined = s["style"] == "line_points"
    ax.plot(x, y, "o-" if joined else "o", ms=3.2 if joined else 2.6, mew=0, alpha=0.8,
            lw=s.get("width", 0.8), color=colour, label=label, zorder=2.5)


def shade_beyond(ax, limit):
    lo, hi = ax.get_xlim()
    if limit < hi:
        ax.axvspan(max(limit, lo), hi, color="0.88", zorder=0, lw=0)
        ax.set_xlim(lo, hi)


def draw_panel(fig, cell, p, legend):
    has_res = "residual" in p
    if has_res:
        sub = cell.subgridspec(2, 1, height_ratios=[PANEL_H, RESID_H], hspace=0.06)
        ax = fig.add_subplot(sub[0])
        axr = fig.add_subplot(sub[1], sharex=ax)
    else:
        ax, axr = fig.add_subplot(cell), None
    for i, s in enumerate(p["series"]):
        c = s.get("colour", -1)
        draw_series(ax, s, PALETTE[(c if c >= 0 else i) % len(PALETTE)])
    ax.set_title(p["title"], y=1.0)  # a fixed y skips matplotlib's title layout
    ax.locator_params(nbins=5)
    ax.set_ylabel(p["ylabel"])
    if legend:
        ax.legend(loc="best")
    if axr is not None:
        r = p["residual"]
        x, y, e = finite(r["x"], r["y"], r.get("yerr"))
        draw_series(axr, dict(r, label=""), "0.3")
        axr.axhline(0.0, color=PALETTE[1], lw=1.2)
        axr.set_ylabel(p.get("residual_label", ""), fontsize=7.5)
        axr.set_title("", y=1.0)
        axr.locator_params(axis="y", nbins=3)
        ax.tick_params(axis="x", labelbottom=False)
        axr.set_xlabel(p["xlabel"])
    else:
        ax.set_xlabel(p["xlabel"])
    if "fit_limit" in p:
        for a in (ax, axr):
            if a is not None:
                shade_beyond(a, p["fit_limit"])
        ax.text(0.99, 0.02, "not fitted", transform=ax.transAxes, ha="right", va="bottom",
                fontsize=7, color="0.35")


def describe(fig, png):
    """What `fig` shows, from its artists (not from the job list; D343)."""
    axes = []
    for ax in fig.axes:
        axes.append({
            "title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
            "lines": [{"label": ln.get_label(), "points": len(ln.get_xdata())}
                      for ln in ax.get_lines() if not ln.get_label().startswith("_")],
            "error_bars": [len(c.get_segments()) for c in ax.collections
                           if isinstance(c, LineCollection)]})
    title = fig._suptitle.get_text() if fig._suptitle is not None else ""
    return {"png": png, "title": title, "axes": axes}


def draw_figure(f, described=None):
    panels = f["panels"]
    cols = max(1, min(int(f.get("columns", 3)), len(panels)))
    rows = math.ceil(len(panels) / cols)
    res = any("residual" in p for p in panels)
    ph = PANEL_H + (RESID_H if res else 0.0) + 0.75  # title, tick labels, x label
    top_in = 0.55 if f.get("title") else 0.2
    fig = plt.figure(figsize=(PANEL_W * cols + 0.6, ph * rows + top_in))
    grid = fig.add_gridspec(rows, cols, left=0.8 / (PANEL_W * cols + 0.6), right=0.985,
                            bottom=0.55 / (ph * rows + top_in),
                            top=1 - top_in / (ph * rows + top_in), wspace=0.32, hspace=0.3)
    seen = set()
    for i, p in enumerate(panels):
        labels = tuple(s["label"] for s in p["series"] if s["label"])
        draw_panel(fig, grid[i // cols, i % cols], p, bool(labels) and labels not in seen)
        seen.add(labels)
    if f.get("title"):
        fig.suptitle(f["title"], fontsize=11, y=1 - 0.18 / (ph * rows + top_in))
    out = f["png"]
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(out) + ".", suffix=".png",
                               dir=os.path.dirname(os.path.abspath(out)))
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=100)
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    if described is not None:
        described.append(describe(fig, out))
    plt.close(fig)
    print("wrote " + out, flush=True)


def write_atomically(path, text):
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".",
                               dir=os.path.dirname(os.path.abspath(path)))
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def main(jobs, describe_out=None):
    with open(jobs) as f:
        spec = json.load(f)
    described = [] if describe_out else None
    for fig in spec["figures"]:
        draw_figure(fig, described)
    if describe_out:
        write_atomically(describe_out, json.dumps({"figures": described}, ensure_ascii=False))


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) == 3 and args[0] == "--describe":
        main(args[2], args[1])
    elif len(args) == 1 and not args[0].startswith("--"):
        main(args[0])
    else:
        sys.exit("usage: plot_figures.py [--describe OUT.json] JOBS.json")
