#!/usr/bin/env python3
"""Writes fcc.data: an argon-like Lennard-Jones FCC crystal (4 x 4 x 4 conventional cells,
256 atoms, LAMMPS units real, atom_style atomic) at the zero-pressure 0 K lattice constant of
the potential of recipe.toml: lj/cut, eps 0.2381 kcal/mol, sigma 3.405 A, cutoff 8.5 A,
not shifted.

The lattice constant solves sum_n r_n phi'(r_n) = 0 over the neighbours within the cutoff
(zero virial = zero pressure at 0 K; no shell lies within 1 % of the cutoff, so the truncation
adds no delta force). Bisection to 1e-13 A. Usage: python3 make_data.py [output]
"""
import itertools
import math
import sys

EPS, SIG, RC, CELLS = 0.2381, 3.405, 8.5, 4


def dphi(r):
    sr6 = (SIG / r) ** 6
    return 4 * EPS * (-12 * sr6 * sr6 + 6 * sr6) / r


def neighbours(a, rc=RC):
    basis = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
    n = int(math.ceil(rc / a)) + 1
    for i, j, k in itertools.product(range(-n, n + 1), repeat=3):
        for b in basis:
            r = a * math.sqrt((i + b[0]) ** 2 + (j + b[1]) ** 2 + (k + b[2]) ** 2)
            if 0 < r < rc:
                yield r


def virial(a):
    return sum(r * dphi(r) for r in neighbours(a))


def lattice_constant():
    lo, hi = 5.0, 5.6  # virial < 0 (compressed: repulsive) at lo, > 0 at hi
    assert virial(lo) < 0 < virial(hi)
    while hi - lo > 1e-13:
        mid = 0.5 * (lo + hi)
        if virial(mid) < 0:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "fcc.data"
    a = lattice_constant()
    shells = sorted(set(round(r, 9) for r in neighbours(a, RC * 1.1)))
    gap = min(abs(r - RC) / RC for r in shells)
    assert gap > 0.01, gap
    L = CELLS * a
    basis = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
    atoms = []
    for i, j, k in itertools.product(range(CELLS), repeat=3):
        for b in basis:
            atoms.append(((i + b[0]) * a, (j + b[1]) * a, (k + b[2]) * a))
    with open(out, "w") as f:
        f.write(f"LJ FCC argon-like crystal, a0 = {a:.15g} A (zero pressure at 0 K, lj/cut 8.5 A)\n\n")
        f.write(f"{len(atoms)} atoms\n1 atom types\n\n")
        for ax in "xyz":
            f.write(f"0.0 {L:.15g} {ax}lo {ax}hi\n")
        f.write("\nMasses\n\n1 39.948\n\nAtoms # atomic\n\n")
        for n, (x, y, z) in enumerate(atoms, 1):
            f.write(f"{n} 1 {x:.15g} {y:.15g} {z:.15g}\n")
    print(f"a0 = {a:.15g} A, {len(atoms)} atoms, box {L:.15g} A, nearest shell gap to cutoff "
          f"{100 * gap:.1f} %")


if __name__ == "__main__":
    main()
