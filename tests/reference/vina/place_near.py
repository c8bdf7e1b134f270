#!/usr/bin/env python3
"""Writes seeded poses of an SDF ligand beside a receptor, for compare.py on receptors
without a ligand of their own (nucleic acids, for example).

    python tests/reference/vina/place_near.py RECEPTOR.pdb LIGAND.sdf N SEED [RESNAME] [-o DIR]

Each pose turns the ligand by a random rotation about its centroid, puts the centroid at the
centre of the receptor's heavy atoms (or of RESNAME's HETATM atoms, when given) and moves it out
along a random direction in 0.25 Å steps until every ligand atom is more than 3.1 Å from every
receptor heavy atom (waters left out). Writes DIR/pose0.sdf ... pose{N-1}.sdf (V2000 only).
"""
import argparse
import os

import numpy as np

WATERS = {"HOH", "WAT", "H2O", "DOD", "TIP", "SOL", "D2O"}


def heavy_atoms(path, resname=None):
    out = []
    for line in open(path):
        if not line.startswith(("ATOM", "HETATM")):
            continue
        if line[76:78].strip() in ("H", "D") or line[17:20].strip() in WATERS:
            continue
        if resname and not (line.startswith("HETATM") and line[17:20].strip() == resname):
            continue
        out.append([float(line[30:38]), float(line[38:46]), float(line[46:54])])
    return np.array(out)


def rotation(q):
    a, b, c, d = q / np.linalg.norm(q)
    return np.array([
        [a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
        [2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)],
        [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]])


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("receptor")
    ap.add_argument("ligand")
    ap.add_argument("n", type=int)
    ap.add_argument("seed", type=int)
    ap.add_argument("resname", nargs="?")
    ap.add_argument("-o", default=".")
    args = ap.parse_args()
    rec = heavy_atoms(args.receptor)
    centre = heavy_atoms(args.receptor, args.resname).mean(axis=0) if args.resname else rec.mean(axis=0)
    lines = open(args.ligand).read().split("\n")
    n_atoms = int(lines[3][:3])
    xyz = np.array([[float(lines[4 + i][k:k + 10]) for k in (0, 10, 20)] for i in range(n_atoms)])
    xyz -= xyz.mean(axis=0)
    rng = np.random.default_rng(args.seed)
    for k in range(args.n):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        turned = xyz @ rotation(rng.normal(size=4)).T
        t = 0.0
        while True:
            z = turned + centre + d * t
            gap = np.min(np.linalg.norm(z[:, None, :] - rec[None, :, :], axis=2))
            if gap > 3.1:
                break
            t += 0.25
        out = list(lines)
        for i in range(n_atoms):
            out[4 + i] = "%10.4f%10.4f%10.4f" % tuple(z[i]) + lines[4 + i][30:]
        with open(os.path.join(args.o, "pose%d.sdf" % k), "w") as f:
            f.write("\n".join(out))
        print("pose%d: moved %.2f Å out, closest receptor atom %.2f Å" % (k, t, gap))


if __name__ == "__main__":
    main()
