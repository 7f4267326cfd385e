#!/usr/bin/env python3
"""The demo's figure goes through pnc's one plot runner (pnc/core/plot.hpp; D337, D363).

Runs `dealii_fracture short.prm --json` (2-D single-edge notch, shortened to the elastic range,
no VTU; ~2 s each) three times into a fresh temporary directory:
- PNC_PYTHON names an interpreter that does not exist: the run still exits 0 and writes
  force_displacement.csv, report.html and report.md; no PNG; stderr has one line
  "dealii_fracture: warning: no plot: <interpreter>: cannot start the Python interpreter ...",
  printed although the run is Quiet; the JSON's "plot" is "failed: " + that warning and
  report.md says "No figure: the plot script failed: " + that warning;
- PNC_SCRIPTS_DIR names an empty directory: the same, the warning naming the variable, the
  directory and plot_force_displacement.py (a missing script is a warning for the demo);
- PNC_PYTHON names a stand-in interpreter that records its arguments and writes the PNG: the
  JSON's "plot" is the PNG, the report has a figure, and the stand-in got exactly [script,
  "--stop", TEXT, CSV, PNG], the script being the build tree's shipped copy (SCRIPTS_DIR),
  byte for byte the source's, and TEXT (which has blanks) one argument: no shell.

Usage: demo_plot_runner.py --demo PATH_TO_dealii_fracture --prm short.prm --card CARD.h5
                           --scripts-dir BUILD/share/pnc/scripts --source-script SCRIPT.py
"""
import argparse
import json
import os
import pathlib
import stat
import subprocess
import sys
import tempfile

FAILURES = []


def check(ok, what):
    if not ok:
        FAILURES.append(what)


def run(a, out, env_extra):
    """The demo into OUT with the extra environment: (exit code, printed object, stderr)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PNC_")}
    env.update(env_extra)
    args = [a.demo, a.prm, "--json", "--set", f"Material/Card={a.card}", "--set",
            f"Output/Directory={out}", "--set", "Output/VTU every=0", "--set",
            "Output/Quiet=true", "--set", "Loading/Path=0, 0.1"]
    r = subprocess.run(args, capture_output=True, text=True, timeout=50, env=env)
    try:
        j = json.loads(r.stdout)
    except ValueError:
        sys.exit(f"demo_plot_runner: {env_extra}: no JSON on stdout (exit {r.returncode}):\n"
                 f"{r.stdout[:400]}\n{r.stderr[-2000:]}")
    return r.returncode, j, r.stderr


def results_written(tag, out, rc):
    check(rc == 0, f"{tag}: exit code {rc}, want 0 (a plot is never what the run is for)")
    csv = out / "force_displacement.csv"
    rows = csv.read_text().splitlines() if csv.is_file() else []
    check(len(rows) >= 3, f"{tag}: {csv} has {len(rows)} lines (header + 2 steps expected)")
    for f in ("report.html", "report.md"):
        check((out / f).is_file(), f"{tag}: no {f}")


def plot_failed(tag, out, rc, j, err, must_name):
    """The run is written and the one warning line is in stderr, the JSON and the report."""
    results_written(tag, out, rc)
    check(not (out / "force_displacement.png").exists(), f"{tag}: a PNG was written")
    prefix = "dealii_fracture: warning: no plot: "
    lines = [x for x in err.splitlines() if x.startswith(prefix)]
    check(len(lines) == 1, f"{tag}: {len(lines)} warning lines, want 1 (Quiet):\n{err[-1500:]}")
    if not lines:
        return
    warning = lines[0][len(prefix):]
    for s in must_name:
        check(s in warning, f"{tag}: the warning does not name '{s}': {warning}")
    check(j.get("plot") == "failed: " + warning, f"{tag}: JSON plot {j.get('plot')!r}")
    md = (out / "report.md").read_text() if (out / "report.md").is_file() else ""
    check("No figure: the plot script failed: " + warning in md,
          f"{tag}: report.md does not carry the warning")


def main():
    ap = argparse.ArgumentParser()
    for o in ("--demo", "--prm", "--card", "--scripts-dir", "--source-script"):
        ap.add_argument(o, required=True)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="pnc_demo_plot_") as tmp:
        t = pathlib.Path(tmp)
        # 1. no interpreter
        missing = t / "no" / "python3"
        out = t / "no_python"
        rc, j, err = run(a, out, {"PNC_PYTHON": str(missing)})
        plot_failed("missing PNC_PYTHON", out, rc, j, err,
                    [str(missing), "cannot start the Python interpreter"])
        # 2. no script where PNC_SCRIPTS_DIR points
        empty = t / "empty"
        empty.mkdir()
        out = t / "no_script"
        rc, j, err = run(a, out, {"PNC_SCRIPTS_DIR": str(empty)})
        plot_failed("empty PNC_SCRIPTS_DIR", out, rc, j, err,
                    ["PNC_SCRIPTS_DIR", str(empty), "plot_force_displacement.py"])
        # 3. a stand-in interpreter: what the runner passes, and a drawn figure
        record = t / "argv.json"
        fake = t / "fake python"  # a blank in the interpreter's path too
        fake.write_text(f"#!{sys.executable}\nimport json, sys\n"
                        f"json.dump(sys.argv[1:], open({str(record)!r}, 'w'))\n"
                        "open(sys.argv[-1], 'wb').write(b'png')\n")
        fake.chmod(fake.stat().st_mode | stat.S_IXUSR)
        out = t / "fake"
        rc, j, err = run(a, out, {"PNC_PYTHON": str(fake)})
        results_written("stand-in interpreter", out, rc)
        png = out / "force_displacement.png"
        check(j.get("plot") == str(png), f"stand-in interpreter: JSON plot {j.get('plot')!r}")
        check("no plot" not in err, f"stand-in interpreter: a warning:\n{err[-1500:]}")
        argv = json.loads(record.read_text()) if record.is_file() else []
        want_script = pathlib.Path(a.scripts_dir) / "plot_force_displacement.py"
        check(len(argv) == 5, f"stand-in interpreter: {len(argv)} arguments {argv}, want 5")
        if len(argv) == 5:
            check(os.path.realpath(argv[0]) == os.path.realpath(want_script),
                  f"stand-in interpreter: script {argv[0]}, want {want_script}")
            check(pathlib.Path(argv[0]).read_bytes() == pathlib.Path(a.source_script).read_bytes(),
                  f"stand-in interpreter: {argv[0]} differs from {a.source_script}")
            check(argv[1] == "--stop" and " " in argv[2], f"stand-in interpreter: {argv[1:3]}")
            check(argv[3:] == [str(out / "force_displacement.csv"), str(png)],
                  f"stand-in interpreter: files {argv[3:]}")
        md = (out / "report.md").read_text() if (out / "report.md").is_file() else ""
        check("No figure" not in md, "stand-in interpreter: the report says it has no figure")
    for f in FAILURES:
        print("FAIL:", f, file=sys.stderr)
    if FAILURES:
        sys.exit(1)
    print("demo_plot_runner: 3 runs: missing interpreter, missing script, stand-in interpreter ok")


if __name__ == "__main__":
    main()
