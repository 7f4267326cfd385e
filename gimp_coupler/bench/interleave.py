#!/usr/bin/env python3
"""Interleaved repetitions of the GIMP step benchmarks (gimp_coupler/bench/README.md, D356).

Runs every (binary, benchmark) pair once per round, rounds repeated --reps times, the order of
the pairs rotated each round, so that a slow phase of a shared machine hits every variant
alike. Reports per variant the median and range (min-max) of particle-steps/s (wall and CPU
time of the calling thread) and, for the ratios, the median and range of the per-round ratios:
  after/before   per-core particle-steps/s of this build vs an older build (e.g. main's),
  2T/1T          2 threads vs 1 thread (wall time),
  crack/no crack wall time per step of the edge-cracked 2-D block vs the plain block.

  gimp_coupler/bench/interleave.py --after build/gimp_coupler/bench_gimp \\
      [--before main-build/gimp_coupler/bench_gimp] [--reps 7] [--min-time 0.2] \\
      [--sizes 10000,100000] [--pin 1] [--ftz] [--json out.json]

--pin CPU runs each benchmark process under `taskset -c CPU` (thread placement test);
--ftz passes --ftz to the after binary (flush-to-zero and denormals-are-zero in the bench).
Load average (uptime) before and after is printed: numbers from a loaded machine are not the
code's scaling. Units: particle-steps/s; ms per step.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys


def run_one(binary, name, min_time, pin, ftz):
    cmd = []
    if pin is not None:
        cmd += ["taskset", "-c", str(pin)]
    cmd += [binary, "--benchmark_filter=^" + name + "$", "--benchmark_format=json",
            "--benchmark_min_time=" + str(min_time)]
    if ftz:
        cmd.append("--ftz")
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    rows = [b for b in json.loads(out)["benchmarks"] if b.get("run_type", "iteration") == "iteration"]
    if len(rows) != 1:
        sys.exit(f"interleave.py: {binary}: benchmark '{name}' matched {len(rows)} runs, expected 1")
    b = rows[0]
    scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b["time_unit"]]
    n = b["particles"]
    wall, cpu = b["real_time"] * scale, b["cpu_time"] * scale
    return {"wall_ms": wall * 1e3, "cpu_ms": cpu * 1e3, "psps_wall": n / wall, "psps_cpu": n / cpu}


def stat(xs):
    return statistics.median(xs), min(xs), max(xs)


def fmt(xs, scale=1.0, digits=2):
    m, lo, hi = (v * scale for v in stat(xs))
    return f"{m:.{digits}f} ({lo:.{digits}f}-{hi:.{digits}f})"


def loadavg():
    with open("/proc/loadavg", encoding="ascii") as f:
        return " ".join(f.read().split()[:3])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--after", required=True, help="bench_gimp of this build")
    ap.add_argument("--before", help="bench_gimp of an older build (e.g. main's)")
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--min-time", type=float, default=0.2, help="s per benchmark run")
    ap.add_argument("--sizes", default="10000,100000", help="particle counts, comma-separated")
    ap.add_argument("--pin", type=int, help="CPU for taskset -c")
    ap.add_argument("--ftz", action="store_true", help="pass --ftz to the after binary")
    ap.add_argument("--json", help="write every sample here (written atomically)")
    a = ap.parse_args()
    for b in [a.after] + ([a.before] if a.before else []):
        if not os.access(b, os.X_OK):
            sys.exit(f"interleave.py: --after/--before '{b}': not an executable file")
    if a.reps < 1:
        sys.exit(f"interleave.py: --reps {a.reps}: must be >= 1")
    try:
        sizes = [int(s) for s in a.sizes.split(",")]
    except ValueError:
        sys.exit(f"interleave.py: --sizes '{a.sizes}': must be particle counts separated by commas")
    if a.min_time <= 0:
        sys.exit(f"interleave.py: --min-time {a.min_time}: must be > 0 (s)")
    variants = []  # (label, binary, benchmark name, ftz)
    for d in (2, 3):
        for n in sizes:
            for t in (1, 2):
                name = f"BM_Step<{d}>/{n}/{t}/0/real_time"
                variants.append((f"{d}-D {n} T{t} after", a.after, name, a.ftz))
                if a.before and t == 1:
                    variants.append((f"{d}-D {n} T{t} before", a.before, name, False))
    for n in sizes:
        variants.append((f"2-D {n} T1 crack after", a.after, f"BM_Step<2>/{n}/1/1/real_time", a.ftz))
    print(f"load average before: {loadavg()}", flush=True)
    samples = {v[0]: [] for v in variants}
    for r in range(a.reps):
        k = r % len(variants)
        for label, binary, name, ftz in variants[k:] + variants[:k]:
            samples[label].append(run_one(binary, name, a.min_time, a.pin, ftz))
        print(f"round {r + 1}/{a.reps} done, load {loadavg()}", file=sys.stderr, flush=True)
    print(f"load average after:  {loadavg()}")
    print(f"{a.reps} interleaved rounds, median (min-max)")
    print(f"{'variant':<28} {'ms/step (wall)':<24} {'M psteps/s wall':<22} {'M psteps/s CPU':<22}")
    for label, *_ in variants:
        s = samples[label]
        print(f"{label:<28} {fmt([x['wall_ms'] for x in s], digits=3):<24} "
              f"{fmt([x['psps_wall'] for x in s], 1e-6):<22} {fmt([x['psps_cpu'] for x in s], 1e-6):<22}")

    def ratio(num, den, key):
        if num not in samples or den not in samples:
            return None
        return [x[key] / y[key] for x, y in zip(samples[num], samples[den])]

    print("ratios of the same round, median (min-max)")
    for d in (2, 3):
        for n in sizes:
            for what, r in (
                ("after/before per core (wall)", ratio(f"{d}-D {n} T1 after", f"{d}-D {n} T1 before", "psps_wall")),
                ("after/before per core (CPU)", ratio(f"{d}-D {n} T1 after", f"{d}-D {n} T1 before", "psps_cpu")),
                ("2T/1T speed-up (wall)", ratio(f"{d}-D {n} T2 after", f"{d}-D {n} T1 after", "psps_wall")),
            ):
                if r:
                    print(f"{d}-D {n:<8} {what:<30} {fmt(r)}")
    for n in sizes:
        for key, what in (("wall_ms", "crack/no crack (wall)"), ("cpu_ms", "crack/no crack (CPU)")):
            r = ratio(f"2-D {n} T1 crack after", f"2-D {n} T1 after", key)
            print(f"2-D {n:<8} {what:<30} {fmt(r)}")
    print("CPU = CPU time of the calling thread (Google Benchmark's default): with 2 threads it "
          "leaves out the worker; on a loaded machine compare 1-thread variants by CPU time")
    if a.json:
        tmp = a.json + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump({"load_at_end": loadavg(), "reps": a.reps, "samples": samples}, f, indent=1)
        os.replace(tmp, a.json)


if __name__ == "__main__":
    main()
