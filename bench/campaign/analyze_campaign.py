#!/usr/bin/env python3
"""Summary of bench_campaign.sh's runs in OUTDIR (times.txt and the run folders).

Wall times per variant (median, range) and the ratios of runs made back to back; and, from
the slurm runs' state files, the Slurm executor's overhead per unit: from the moment the unit
could start to the moment it started. A unit can start when its job was submitted, every unit
it needs has ended, and a CPU is free (fewer than CPUS units running: the test cluster has 2
CPUs and every unit here takes one); the time it then waits is the scheduler's and pnc's
(sbatch, dependency release, job launch, pnc start-up). Python 3 standard library only.

    analyze_campaign.py OUTDIR [CPUS]
"""
import json
import os
import statistics
import sys


def wall_times(out):
    t = {}
    for line in open(os.path.join(out, "times.txt")):
        v, rep, s = line.split()[:3]
        t.setdefault(v, {})[int(rep)] = float(s)
    return t


def could_start(u, st, units, cpus):
    s = st[u["id"]]
    ready = max([s.get("queued_s", 0.0)] + [st[n]["ended_s"] for n in u["needs"]])
    # the earliest time >= ready with fewer than `cpus` other units running
    others = [(st[o["id"]]["started_s"], st[o["id"]]["ended_s"]) for o in units
              if o["id"] != u["id"] and st[o["id"]].get("started_s", 0) > 0]
    candidates = sorted({ready} | {e for _, e in others if e > ready})
    for t in candidates:
        if sum(1 for a, e in others if a <= t < e) < cpus:
            return t
    return ready


def overheads(out, cpus):
    lat = []
    for d in sorted(os.listdir(out)):
        path = os.path.join(out, d)
        if not d.startswith("slurm-") or not os.path.isdir(path):
            continue
        units = json.load(open(os.path.join(path, "plan.json")))["units"]
        st = {u["id"]: json.load(open(os.path.join(path, "state", u["id"] + ".json")))
              for u in units}
        for u in units:
            s = st[u["id"]]
            if s.get("started_s", 0) > 0 and s.get("queued_s", 0) > 0:
                lat.append((u["kind"], s["started_s"] - could_start(u, st, units, cpus)))
    return lat


def main():
    out = sys.argv[1]
    cpus = int(sys.argv[2]) if len(sys.argv) > 2 else 2
    t = wall_times(out)
    lines = []
    for v in sorted(t):
        xs = list(t[v].values())
        lines.append(f"{v}: median {statistics.median(xs):.1f} s, range {min(xs):.1f}-"
                     f"{max(xs):.1f} s ({len(xs)} runs)")

    def ratio(a, b):
        r = [t[a][k] / t[b][k] for k in t.get(a, {}) if k in t.get(b, {})]
        if r:
            lines.append(f"{a}/{b}: median {statistics.median(r):.3f}, range {min(r):.3f}-"
                         f"{max(r):.3f} ({len(r)} pairs run back to back)")

    ratio("local", "base")
    ratio("local", "base1")
    ratio("slurm", "local")
    lat = overheads(out, cpus)
    if lat:
        xs = [x for _, x in lat]
        lines.append(f"slurm overhead per unit (could start -> started): median "
                     f"{statistics.median(xs):.2f} s, range {min(xs):.2f}-{max(xs):.2f} s over "
                     f"{len(xs)} units")
        for k in sorted({k for k, _ in lat}):
            ks = [x for kk, x in lat if kk == k]
            lines.append(f"  {k}: median {statistics.median(ks):.2f} s, range {min(ks):.2f}-"
                         f"{max(ks):.2f} s ({len(ks)} units)")
    text = "\n".join(lines) + "\n"
    open(os.path.join(out, "summary.txt"), "w").write(text)
    sys.stdout.write(text)


if __name__ == "__main__":
    main()
