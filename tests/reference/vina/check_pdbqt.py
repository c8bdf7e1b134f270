#!/usr/bin/env python3
"""Checks that bump, reading PDBQT files, scores them as AutoDock Vina 1.2 does.

    python tests/reference/vina/check_pdbqt.py [--pdb-dir ../shared/pdb] [--plb CHECKOUT]
                                               [--vina-examples CHECKOUT]
                                               [--bump target/release/bump] [--work DIR]

For every complex of make_reference.py (prepared exactly as there: a rigid receptor PDBQT and a
ligand PDBQT with its torsion tree, both written by Open Babel) and, with --plb, the first
ligand of every target of the Open Force Field protein-ligand benchmark checkout (receptor as
given, written rigid by Open Babel): the ligand is also written by Meeko (0.8, from the same
RDKit molecule). With --vina-examples, AutoDock Vina's own example files as given (receptors
from ADFR, ligands from Meeko, docking outputs; a model of an output is scored as a file of its
own). Each ligand file is scored at its pose by Vina (vina.Vina.score(), both
scoring functions) and by `bump score RECEPTOR.pdbqt LIGAND.pdbqt --json`; the table gives
Vina's total, inter and intra and bump's differences. Exits with status 1 when a total or an
intermolecular energy differs by more than 1e-3 kcal/mol: they agree to 1e-5 but where a pair
lies on an edge of Vina's table (32 r^2 a whole number, which three-decimal coordinates give
about once in thirty complexes), and bump, which keeps atoms in f32 about their molecule's
centre, reads the neighbouring sample (1e-4 to 1e-3). The intramolecular energy of a
macrocycle Meeko opened (its CG/G pseudo-atoms) differs by design: bump holds the ring and does
not compute Vina's glue term (docs/vina-scoring.md).
Requirements: requirements.txt beside this script, and a release build of bump.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_reference as mr  # noqa: E402

FUNCTIONS = (("vina", mr.VINA_WEIGHTS), ("vinardo", mr.VINARDO_WEIGHTS))


def meeko_pdbqt(mol, path):
    from meeko import MoleculePreparation, PDBQTWriterLegacy
    setups = MoleculePreparation().prepare(mol)
    text, ok, err = PDBQTWriterLegacy.write_string(setups[0])
    if not ok:
        raise RuntimeError(err)
    open(path, "w").write(text)


def pdbqt_xyz(text):
    return np.array([[float(l[30:38]), float(l[38:46]), float(l[46:54])]
                     for l in text.splitlines() if l.startswith(("ATOM", "HETATM"))])


def score_both(bump, receptor, ligand):
    """[(function, vina (total, inter, intra), bump (total, inter, intra), bump N_tors)]."""
    text = open(ligand).read()
    centre = pdbqt_xyz(text).mean(axis=0)
    out = []
    for sf, w in FUNCTIONS:
        v = mr.vina_session(sf, w, receptor, text, centre, [40, 40, 40], 1.0)
        s = list(v._vina.score())
        run = subprocess.run([bump, "score", receptor, ligand, "--scoring", sf, "--json"],
                             capture_output=True, text=True)
        if run.returncode != 0:
            raise RuntimeError("bump score %s %s: %s" % (receptor, ligand, run.stderr.strip()))
        j = json.loads(run.stdout)
        out.append((sf, (s[0], s[1], s[5]), (j["total"], j["inter"], j["intra"]),
                    j["torsion_count"]))
    return out


def plb_inputs(checkout, work):
    from rdkit import Chem
    data = os.path.join(checkout, "data")
    for target in sorted(os.listdir(data)):
        prot = os.path.join(data, target, "01_protein", "crd", "protein.pdb")
        lig_sdf = os.path.join(data, target, "02_ligands", "ligands.sdf")
        if not (os.path.isfile(lig_sdf) and os.path.isfile(prot)):
            continue
        rec = os.path.join(work, target + "_rec.pdbqt")
        mr.ob_to_pdbqt(prot, "pdb", rec, add_h=False, rigid=True)
        mol = next(Chem.SDMolSupplier(lig_sdf, removeHs=False))
        sdf = os.path.join(work, target + "_lig.sdf")
        Chem.MolToMolFile(mol, sdf)
        obl = os.path.join(work, target + "_lig.pdbqt")
        mr.ob_to_pdbqt(sdf, "sdf", obl, add_h=False, rigid=False)
        mk = os.path.join(work, target + "_lig_meeko.pdbqt")
        meeko_pdbqt(mol, mk)
        yield "plb " + target, rec, [("obabel", obl), ("meeko", mk)]


# AutoDock Vina's own example files (example/*/solution of its repository): (name, receptor,
# ligand, model or None).
VINA_EXAMPLES = [
    ("basic_docking", "basic_docking/solution/1iep_receptor.pdbqt",
     "basic_docking/solution/1iep_ligand.pdbqt", None),
    ("basic_docking out, pose 1", "basic_docking/solution/1iep_receptor.pdbqt",
     "basic_docking/solution/1iep_ligand_vina_out.pdbqt", 1),
    ("basic_docking out, pose 2", "basic_docking/solution/1iep_receptor.pdbqt",
     "basic_docking/solution/1iep_ligand_vina_out.pdbqt", 2),
    ("docking_with_macrocycles", "docking_with_macrocycles/solution/BACE_1_receptor.pdbqt",
     "docking_with_macrocycles/solution/BACE_1_ligand.pdbqt", None),
    ("docking_with_macrocycles out, pose 2",
     "docking_with_macrocycles/solution/BACE_1_receptor.pdbqt",
     "docking_with_macrocycles/solution/BACE_1_ligand_vina_out.pdbqt", 2),
    ("docking_with_zinc_metalloproteins", "docking_with_zinc_metalloproteins/solution/protein.pdbqt",
     "docking_with_zinc_metalloproteins/solution/1s63_ligand.pdbqt", None),
    ("flexible_docking, rigid part", "flexible_docking/solution/1fpu_receptor_rigid.pdbqt",
     "flexible_docking/solution/1iep_ligand.pdbqt", None),
]


def model_text(path, n):
    out, cur, keep = [], 0, False
    for line in open(path):
        if line.startswith("MODEL"):
            cur += 1
            keep = cur == n
        elif line.startswith("ENDMDL"):
            keep = False
        elif keep:
            out.append(line)
    return "".join(out)


def example_inputs(checkout, work):
    base = os.path.join(checkout, "example")
    for name, rec, lig, model in VINA_EXAMPLES:
        lig = os.path.join(base, lig)
        if model:
            path = os.path.join(work, "%s_%d.pdbqt" % (os.path.basename(lig)[:-6], model))
            open(path, "w").write(model_text(lig, model))
            lig = path
        yield "Vina example " + name, os.path.join(base, rec), [("as given", lig)]


def shared_inputs(pdb_dir, work):
    for cx in mr.COMPLEXES:
        info, rec, lig, mol, *_ = mr.prepare_complex(cx, pdb_dir, work)
        mk = os.path.join(work, cx["id"] + "_lig_meeko.pdbqt")
        meeko_pdbqt(mol, mk)
        yield cx["id"], rec, [("obabel", lig), ("meeko", mk)]


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pdb-dir", default=os.path.join(HERE, "../../../../shared/pdb"))
    ap.add_argument("--plb", help="an Open Force Field protein-ligand-benchmark checkout")
    ap.add_argument("--vina-examples", metavar="CHECKOUT",
                    help="an AutoDock Vina checkout: score its example/*/solution files as given")
    ap.add_argument("--bump", default="target/release/bump")
    ap.add_argument("--work", help="keep the prepared files here")
    args = ap.parse_args()
    work = args.work or tempfile.mkdtemp(prefix="bump-pdbqt-")
    os.makedirs(work, exist_ok=True)
    sources = [shared_inputs(args.pdb_dir, work)]
    if args.plb:
        sources.append(plb_inputs(args.plb, work))
    if args.vina_examples:
        sources.append(example_inputs(args.vina_examples, work))
    print("| complex | ligand PDBQT | N_tors | vina total | inter | intra | vinardo total "
          "| worst \\|Δ total\\|, \\|Δ inter\\| | \\|Δ intra\\| |")
    print("|---|---|---|---|---|---|---|---|---|")
    worst = 0.0
    for source in sources:
        for name, rec, ligands in source:
            for writer, lig in ligands:
                rows = score_both(args.bump, rec, lig)
                d_main = max(abs(b[k] - v[k]) for _, v, b, _ in rows for k in (0, 1))
                d_intra = max(abs(b[2] - v[2]) for _, v, b, _ in rows)
                worst = max(worst, d_main)
                (_, v, _, ntors), (_, vd, _, _) = rows
                print("| %s | %s | %g | %.3f | %.3f | %.3f | %.3f | %.0e | %.0e |" % (
                    name, writer, ntors, v[0], v[1], v[2], vd[0], d_main, d_intra), flush=True)
    print("worst |Δ total|, |Δ inter| over every file and function: %.1e kcal/mol" % worst)
    return 1 if worst > 1e-3 else 0


if __name__ == "__main__":
    sys.exit(main())
