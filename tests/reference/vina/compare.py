#!/usr/bin/env python3
"""Scores one receptor and ligand with AutoDock Vina 1.2 and with `bump score`, and compares.

For complexes outside the shared folder (the committed reference covers only those): the
receptor and ligand are prepared for Vina exactly as make_reference.py prepares the shared
ones (Open Babel receptor PDBQT with hydrogens, RDKit hydrogens and an Open Babel torsion tree
for the ligand), and bump reads the same receptor atoms and the ligand file as given.

    python tests/reference/vina/compare.py RECEPTOR.pdb LIGAND.sdf [--bump PATH] [--as-is]

By default the receptor is its polymer (ATOM) records, as in the reference; `--as-is` gives
Vina and bump the whole file but its waters (ions, cofactors and modified residues included;
bump always leaves waters out). Prints, for vina and
vinardo, Vina's and bump's inter, intra and total, and exits with status 1 when an
intermolecular energy differs by more than 0.1 kcal/mol + 3 % (issue 43's tolerance).
Requirements: requirements.txt beside this script, and a release build of bump.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_reference as mr  # noqa: E402


# bump's water names (model::WATER_NAMES), as PDB's three columns hold them.
WATERS = {"HOH", "WAT", "H2O", "DOD", "TIP", "TIP3", "SOL", "D2O"}


def bump_score(bump, receptor, ligand, sf):
    out = subprocess.run([bump, "score", receptor, ligand, "--scoring", sf, "--json"],
                         capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError("bump score failed: " + out.stderr.strip()[:500])
    for line in out.stderr.splitlines():
        print("  bump:", line[:200])
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("receptor")
    ap.add_argument("ligand", help="SDF")
    ap.add_argument("--bump", default="target/release/bump")
    ap.add_argument("--as-is", action="store_true",
                    help="give both programs the whole receptor file but its waters")
    args = ap.parse_args()
    receptor, ligand = os.path.abspath(args.receptor), os.path.abspath(args.ligand)
    worst = 0.0
    with tempfile.TemporaryDirectory() as work:
        cx = dict(id="cmp", receptor=receptor, ligand=None, sdf=ligand)
        _, rec_pdbqt, lig_pdbqt, _, _, _, orig, _ = mr.prepare_complex(cx, "", work)
        rec_for_bump = os.path.join(work, "cmp_rec.pdb")
        if args.as_is:
            rec_pdbqt = os.path.join(work, "cmp_whole.pdbqt")
            dry = os.path.join(work, "cmp_dry.pdb")
            with open(receptor) as src, open(dry, "w") as out:
                out.writelines(l for l in src if not (l.startswith(("ATOM", "HETATM"))
                                                      and l[17:20].strip() in WATERS))
            mr.ob_to_pdbqt(dry, "pdb", rec_pdbqt, add_h=True, rigid=True)
            rec_for_bump = receptor
        text = open(lig_pdbqt).read()
        xyz = np.array(orig)
        centre = np.round(xyz.mean(axis=0), 3)
        size = np.ceil(2 * (np.max(np.abs(xyz - centre), axis=0) + mr.BOX_MARGIN))
        print("%-8s %28s %28s  %s" % ("", "Vina: inter intra total", "bump: inter intra total",
                                      "|d inter| / tolerance"))
        for sf, weights in (("vina", mr.VINA_WEIGHTS), ("vinardo", mr.VINARDO_WEIGHTS)):
            v = mr.vina_session(sf, weights, rec_pdbqt, text, centre, size, mr.SCORE_SPACING)
            s = list(v._vina.score())
            b = bump_score(args.bump, rec_for_bump, ligand, sf)
            tol = 0.1 + 0.03 * abs(s[1])
            d = abs(b["inter"] - s[1])
            worst = max(worst, d / tol)
            print("%-8s %9.3f %8.3f %9.3f %9.3f %8.3f %9.3f  %.3f / %.3f" % (
                sf, s[1], s[5], s[0], b["inter"], b["intra"], b["total"], d, tol))
    if worst > 1.0:
        print("DISAGREE: an intermolecular energy differs by more than the tolerance")
        sys.exit(1)
    print("agree")


if __name__ == "__main__":
    main()
