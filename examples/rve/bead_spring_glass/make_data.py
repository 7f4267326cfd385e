#!/usr/bin/env python3
"""Writes chains.data: a Kremer-Grest bead-spring melt (20 chains x 30 beads = 600 beads,
LAMMPS units real, atom_style molecular) for recipe.toml.

Reduced units mapped to real: sigma = 4.0 A, epsilon = 0.3 kcal/mol, bead mass 50 g/mol.
Chains are self-avoiding random walks on a periodic simple cubic lattice of spacing sigma
(9 x 9 x 9 sites, 36 A box): every bond is sigma long (well inside the FENE range 1.5 sigma)
and no two beads overlap, so the first stage (an energy minimisation) starts from a sane
state. Deterministic (seed 7). Usage: python3 make_data.py [output]
"""
import random
import sys

SIGMA, MASS, N_SIDE, CHAINS, BEADS, SEED = 4.0, 50.0, 9, 20, 30, 7
STEPS = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]


def grow(rng, occupied):
    """One self-avoiding walk of BEADS sites (unwrapped lattice coordinates), or None."""
    free = [(i, j, k) for i in range(N_SIDE) for j in range(N_SIDE) for k in range(N_SIDE)
            if (i, j, k) not in occupied]
    walk = [rng.choice(free)]
    taken = {walk[0]}
    while len(walk) < BEADS:
        x = walk[-1]
        options = []
        for d in STEPS:
            y = (x[0] + d[0], x[1] + d[1], x[2] + d[2])
            w = (y[0] % N_SIDE, y[1] % N_SIDE, y[2] % N_SIDE)
            if w not in occupied and w not in taken:
                options.append((y, w))
        if not options:
            return None
        y, w = rng.choice(options)
        walk.append(y)
        taken.add(w)
    return walk


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "chains.data"
    rng = random.Random(SEED)
    occupied, chains = set(), []
    while len(chains) < CHAINS:
        for _ in range(10000):
            w = grow(rng, occupied)
            if w:
                break
        else:
            sys.exit("could not place a chain; lower CHAINS or BEADS")
        chains.append(w)
        occupied.update((y[0] % N_SIDE, y[1] % N_SIDE, y[2] % N_SIDE) for y in w)
    L = N_SIDE * SIGMA
    n = CHAINS * BEADS
    with open(out, "w") as f:
        f.write(f"Kremer-Grest bead-spring melt, {CHAINS} chains x {BEADS} beads, lattice walks "
                f"(sigma {SIGMA} A)\n\n")
        f.write(f"{n} atoms\n{CHAINS * (BEADS - 1)} bonds\n1 atom types\n1 bond types\n\n")
        for ax in "xyz":
            f.write(f"0.0 {L:.6f} {ax}lo {ax}hi\n")
        f.write(f"\nMasses\n\n1 {MASS}\n\nAtoms # molecular\n\n")
        idx = 0
        for c, w in enumerate(chains, 1):
            for y in w:
                idx += 1
                img = [y[a] // N_SIDE for a in range(3)]
                pos = [(y[a] % N_SIDE + 0.5) * SIGMA for a in range(3)]
                f.write(f"{idx} {c} 1 {pos[0]:.6f} {pos[1]:.6f} {pos[2]:.6f} "
                        f"{img[0]} {img[1]} {img[2]}\n")
        f.write("\nBonds\n\n")
        b = 0
        for c in range(CHAINS):
            for i in range(BEADS - 1):
                b += 1
                a1 = c * BEADS + i + 1
                f.write(f"{b} 1 {a1} {a1 + 1}\n")
    print(f"{n} beads, {CHAINS * (BEADS - 1)} bonds, box {L} A, density "
          f"{n * MASS / (L ** 3 * 0.602214076):.4f} g/cm3")


if __name__ == "__main__":
    main()
