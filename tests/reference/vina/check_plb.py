#!/usr/bin/env python3
"""Checks bump's score and settle on complexes outside the shared folder: the Open Force Field
protein-ligand benchmark (https://github.com/openforcefield/protein-ligand-benchmark).

    python tests/reference/vina/check_plb.py PLB_CHECKOUT [--bump PATH] [--work DIR]

For every target under PLB_CHECKOUT/data with a protein.pdb and a ligands.sdf: the first and the
middle ligand record are scored by AutoDock Vina and by `bump score` with compare.py, against
the receptor as given (with its hydrogens) and with every hydrogen removed (as a crystal
structure comes); then the first ligand is shifted up to 1.5 Å and turned up to 30° (8 seeded
perturbations) and `bump settle` runs against the receptor without hydrogens: how many return
within 1 Å heavy-atom RMSD of the file pose, and how many end in a collision. Last, each picked
ligand is written as a bare PDB residue by Open Babel (HETATM records, no CONECT, charges in
columns 79-80), with its hydrogens and without, and `bump score` of each (bump perceiving the
chemistry) is compared with its score of the SDF: inter and intra within 0.01 kcal/mol (the
PDB's three decimals) and the same torsion count. Exits with status 1 when an intermolecular
energy differs from Vina's by more than compare.py's tolerance.
Requirements: requirements.txt beside this script, and a release build of bump.
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def records(path):
    """The SDF file's records, each ending in $$$$."""
    text = open(path).read()
    return [r.strip("\n") + "\n$$$$\n" for r in text.split("$$$$") if r.strip()]


def heavy_atoms(sdf_text):
    """Heavy-atom coordinates of the first molecule of a V2000 SDF text."""
    lines = sdf_text.split("\n")
    n = int(lines[3][:3])
    out = []
    for line in lines[4:4 + n]:
        if line[31:34].strip() != "H":
            out.append((float(line[:10]), float(line[10:20]), float(line[20:30])))
    return out


def rmsd(a, b):
    return math.sqrt(sum((x - y) ** 2 for p, q in zip(a, b) for x, y in zip(p, q)) / len(a))


def compare(bump, receptor, ligand):
    """(vina |d inter|, vinardo |d inter|, Vina's inter, agrees) from compare.py."""
    out = subprocess.run([sys.executable, os.path.join(HERE, "compare.py"), receptor, ligand,
                          "--bump", bump], capture_output=True, text=True)
    rows = {l.split()[0]: l.split() for l in out.stdout.splitlines()
            if l.startswith(("vina ", "vinardo "))}
    if set(rows) != {"vina", "vinardo"}:
        raise RuntimeError("compare.py failed on %s: %s" % (ligand, out.stderr.strip()[-500:]))
    return float(rows["vina"][7]), float(rows["vinardo"][7]), float(rows["vina"][1]), \
        out.returncode == 0


def settle_runs(bump, receptor, ligand, work, runs=8, seed=7):
    """(returned within 1 Å, ended colliding, median RMSD) over seeded perturbations."""
    want = heavy_atoms(open(ligand).read())
    rng = random.Random(seed)
    returned, colliding, found = 0, 0, []
    for k in range(runs):
        while True:
            v = [rng.uniform(-1, 1) for _ in range(3)]
            if 0 < sum(x * x for x in v) <= 1:
                break
        move = ",".join("%.4f" % (1.5 * x) for x in v)
        axis = [rng.gauss(0, 1) for _ in range(3)]
        turn = ",".join("%.4f" % x for x in axis) + ",%.3f" % (30 * rng.random())
        out = os.path.join(work, "settled_%d.sdf" % k)
        p = subprocess.run([bump, "settle", receptor, ligand, "--move=" + move, "--turn=" + turn,
                            "-o", out, "--json"], capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError("bump settle failed: " + p.stderr.strip()[:500])
        r = rmsd(heavy_atoms(open(out).read()), want)
        found.append(r)
        returned += r < 1.0
        colliding += bool(json.loads(p.stdout)["end_collisions"])
    found.sort()
    return returned, colliding, found[len(found) // 2]


def bump_score(bump, receptor, ligand):
    p = subprocess.run([bump, "score", receptor, ligand, "--json"], capture_output=True,
                       text=True)
    if p.returncode != 0:
        raise RuntimeError("bump score failed on %s: %s" % (ligand, p.stderr.strip()[:500]))
    j = json.loads(p.stdout)
    return j["inter"], j["intra"], j["torsion_count"]


def as_bare_pdb(sdf, work, stem):
    """The SDF's molecule as Open Babel writes it to PDB, with and without hydrogens, its
    CONECT records left out: (with, without)."""
    from openbabel import pybel
    mol = next(pybel.readfile("sdf", sdf))
    atoms = [l for l in mol.write("pdb").splitlines() if l.startswith(("ATOM", "HETATM"))]
    out = []
    for keep_h in (True, False):
        path = os.path.join(work, "%s_%s.pdb" % (stem, "h" if keep_h else "noh"))
        with open(path, "w") as f:
            f.write("\n".join(l for l in atoms if keep_h or l[76:78].strip() != "H") + "\nEND\n")
        out.append(path)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plb", help="a checkout of openforcefield/protein-ligand-benchmark")
    ap.add_argument("--bump", default="target/release/bump")
    args = ap.parse_args()
    bump = os.path.abspath(args.bump)
    data = os.path.join(args.plb, "data")
    worst = {"vina": 0.0, "vinardo": 0.0}
    ok = True
    print("| target | ligand records | Vina inter (without H) | worst vina / vinardo |d inter| "
          "(with H) | (without H) | settle returned within 1 Å | ends colliding | median RMSD Å "
          "| as bare PDB, scored as the SDF |")
    print("|---|---|---|---|---|---|---|---|---|")
    for target in sorted(os.listdir(data)):
        protein = os.path.join(data, target, "01_protein", "crd", "protein.pdb")
        ligands = os.path.join(data, target, "02_ligands", "ligands.sdf")
        if not (os.path.isfile(protein) and os.path.isfile(ligands)):
            continue
        with tempfile.TemporaryDirectory() as work:
            noh = os.path.join(work, "protein_noh.pdb")
            with open(protein) as src, open(noh, "w") as dst:
                dst.writelines(l for l in src if not (l.startswith(("ATOM", "HETATM"))
                                                      and l[76:78].strip() == "H"))
            recs = records(ligands)
            picked = sorted({0, len(recs) // 2})
            inter, cols = [], {True: [0.0, 0.0], False: [0.0, 0.0]}
            perceived = 0
            for i in picked:
                lig = os.path.join(work, "lig%d.sdf" % i)
                open(lig, "w").write(recs[i])
                for with_h, rec in ((True, protein), (False, noh)):
                    dv, dd, e, agrees = compare(bump, rec, lig)
                    ok &= agrees
                    cols[with_h] = [max(cols[with_h][0], dv), max(cols[with_h][1], dd)]
                    worst["vina"] = max(worst["vina"], dv)
                    worst["vinardo"] = max(worst["vinardo"], dd)
                inter.append(e)
                want = bump_score(bump, noh, lig)
                same = True
                for pdb in as_bare_pdb(lig, work, "lig%d" % i):
                    got = bump_score(bump, noh, pdb)
                    same &= abs(got[0] - want[0]) <= 0.01 and abs(got[1] - want[1]) <= 0.01 \
                        and got[2] == want[2]
                perceived += same
            back, coll, med = settle_runs(bump, noh, os.path.join(work, "lig0.sdf"), work)
        print("| %s | %s | %s | %.3f / %.3f | %.3f / %.3f | %d of 8 | %d | %.2f | %d of %d |" % (
            target, ", ".join(str(i + 1) for i in picked), ", ".join("%.3f" % e for e in inter),
            *cols[True], *cols[False], back, coll, med, perceived, len(picked)), flush=True)
    print("worst |d inter|: vina %.3f, vinardo %.3f kcal/mol" % (worst["vina"], worst["vinardo"]))
    if not ok:
        print("DISAGREE: an intermolecular energy differs by more than the tolerance")
        sys.exit(1)


if __name__ == "__main__":
    main()
