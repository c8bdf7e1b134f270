#!/usr/bin/env python3
"""A small synthetic PDBQT test set with AutoDock Vina 1.2.7 reference scores.

Run from the repository root (Python 3.11, packages pinned in requirements.txt; no network,
no input files):

    python tests/reference/vina/make_pdbqt.py [--out tests/data/pdbqt]

It is for a test that reads PDBQT files the way users have them (written by Open Babel, meeko
and Vina itself) and checks that bump scores them exactly as Vina does. Everything is built
from SMILES with RDKit (seeded ETKDGv3 embedding, MMFF minimisation; single-threaded, so the
output is deterministic for the pinned package versions); nothing is read from any structure
file. It writes into the output folder:

* receptor.pdbqt -- a rigid synthetic "pocket": thirteen capped amino acids (ACE-X-NME,
  X = ASP GLU SER LYS ARG HIS TYR TRP PHE ASN LEU MET CYS; Lys, Arg, Asp, Glu charged; His
  protonated on ND1) embedded from SMILES with all hydrogens, placed by a seeded search around
  the ligand site at contact distances (heavy-atom pairs N/O-N/O >= 2.7 A, others >= 3.2 A, so
  every Vina term is non-zero for every ligand), chains A and B, PDB atom names, plus one Zn2+
  (HETATM ZN) >= 2.8 A from every ligand atom and every receptor heavy atom. The PDB (with the
  RDKit hydrogens and formal charges in columns 79-80) becomes a PDBQT through the Open Babel
  python API as make_reference.py prepares receptors (ob_to_pdbqt: Gasteiger charges, rigid
  writer 'r', polar hydrogens kept as HD, non-polar ones merged), except that hydrogens are not
  added (add_h=False): the RDKit ones are all there, and Open Babel would protonate a
  carboxylate it reads as C-O.
* lig1/lig2/lig3 -- three drug-like ligands (see LIGANDS), embedded with RDKit and placed with
  their heavy-atom centroid at the origin and principal axes along x, y, z (a rotation, never a
  reflection); each written twice: ligN_meeko.pdbqt (meeko MoleculePreparation +
  PDBQTWriterLegacy from the RDKit molecule with explicit hydrogens) and ligN_obabel.pdbqt
  (Open Babel python API from an RDKit SDF, torsion tree, Gasteiger charges: make_reference's
  ob_to_pdbqt, i.e. 'obabel lig.sdf --partialcharge gasteiger -O lig.pdbqt').
* dock_out.pdbqt -- vina.Vina(sf_name='vina', seed=DOCK_SEED, cpu=1) docking of lig1_meeko
  into a box around the pocket (exhaustiveness 2, n_poses 3), as written by write_poses.
* values.json -- Vina's types and scores (sorted keys, floats with 6 decimals):
  receptor.atoms: every heavy receptor atom (index: 0-based position among the file's
  ATOM/HETATM records, needed because Open Babel writes each disconnected piece -- here each
  capped residue -- as its own block with serials restarting at 1; serial, chain, resname,
  resnum, name, AD type, XS type); ligands[file]: model,
  TORSDOF, Vina's num_tors (the N_tors of 1 + 0.05846 N_tors, conf_independent_inputs), every
  heavy atom (serial, AD, XS) and poses: the file as is (shift 0) and, for the six ligand
  files, three seeded pure translations of every atom (same shifts for a ligand's meeko and
  Open Babel files; 3 decimals, at most 1 A), each scored with sf_name 'vina' and 'vinardo':
  total = score()[0], inter = lig_inter = score()[1], intra = lig_intra = score()[5].
  One entry per MODEL of dock_out.pdbqt ("dock_out.pdbqt#1" ...), zero shift only.

Scores are taken exactly as make_reference.py takes them: set_receptor, set_ligand_from_string,
compute_vina_maps (spacing 1 A, a box around every scored pose plus 6 A, only to satisfy
score()'s box check), then the unrounded Vina._vina.score() (Vina.score() rounds to 3 decimals).
XS types, bonds, num_tors and intramolecular pairs come from make_reference.py's transcription
of Vina's PDBQT parsing and typing; the script re-computes every score and, term by term, every
unweighted inter and intra sum with them (make_reference.reimpl_score) and fails if any differs
from Vina by more than 1e-4. It also fails if some ligand file at shift 0 has a zero Vina or
Vinardo term. Running it twice gives identical files.
"""
import argparse
import json
import math
import os
import shutil
import sys
import tempfile
import zlib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_reference as mr  # noqa: E402

# ----------------------------------------------------------------------------------------------
# Molecules
# ----------------------------------------------------------------------------------------------
LIGANDS = [
    # amide, carboxylate, hydroxyl
    ("lig1", "[O-]C(=O)c1ccc(cc1)C(=O)N[C@@H](CO)Cc1ccccc1"),
    # F, Cl, Br, pyridine N (acceptor), sulfonamide
    ("lig2", "Fc1ccc(cc1Cl)S(=O)(=O)Nc1ccc(Br)cn1"),
    # benzamidinium with a 6-carbon ether chain ending in a hydroxyl (>= 6 rotatable bonds)
    ("lig3", "NC(=[NH2+])c1ccc(cc1)OCCCCCCO"),
]
LIGAND_SEED = 20240611
RECEPTOR_SEED = 7031
SHIFT_SEED = "pdbqt-shift"
N_SHIFTS = 3
DOCK_SEED = 1234

# Capped residue: ACE (maps 1-3), the residue (4-7 backbone, 10+ side chain), NME (8-9).
BACKBONE = "[CH3:1][C:2](=[O:3])[NH:4][C@@H:5]({side})[C:6](=[O:7])[NH:8][CH3:9]"
BB_NAMES = {1: ("ACE", "CH3"), 2: ("ACE", "C"), 3: ("ACE", "O"), 4: (None, "N"), 5: (None, "CA"),
            6: (None, "C"), 7: (None, "O"), 8: ("NME", "N"), 9: ("NME", "C")}
SIDE = {
    "ASP": ("[CH2:10][C:11](=[O:12])[O-:13]", ["CB", "CG", "OD1", "OD2"]),
    "GLU": ("[CH2:10][CH2:11][C:12](=[O:13])[O-:14]", ["CB", "CG", "CD", "OE1", "OE2"]),
    "SER": ("[CH2:10][OH:11]", ["CB", "OG"]),
    "LYS": ("[CH2:10][CH2:11][CH2:12][CH2:13][NH3+:14]", ["CB", "CG", "CD", "CE", "NZ"]),
    "ARG": ("[CH2:10][CH2:11][CH2:12][NH:13][C:14](=[NH2+:15])[NH2:16]",
            ["CB", "CG", "CD", "NE", "CZ", "NH1", "NH2"]),
    "HIS": ("[CH2:10][c:11]1[nH:12][cH:13][n:14][cH:15]1", ["CB", "CG", "ND1", "CE1", "NE2", "CD2"]),
    "TYR": ("[CH2:10][c:11]1[cH:12][cH:13][c:14]([OH:15])[cH:16][cH:17]1",
            ["CB", "CG", "CD1", "CE1", "CZ", "OH", "CE2", "CD2"]),
    "TRP": ("[CH2:10][c:11]1[cH:12][nH:13][c:14]2[cH:15][cH:16][cH:17][cH:18][c:19]12",
            ["CB", "CG", "CD1", "NE1", "CE2", "CZ2", "CH2", "CZ3", "CE3", "CD2"]),
    "PHE": ("[CH2:10][c:11]1[cH:12][cH:13][cH:14][cH:15][cH:16]1",
            ["CB", "CG", "CD1", "CE1", "CZ", "CE2", "CD2"]),
    "ASN": ("[CH2:10][C:11](=[O:12])[NH2:13]", ["CB", "CG", "OD1", "ND2"]),
    "LEU": ("[CH2:10][CH:11]([CH3:12])[CH3:13]", ["CB", "CG", "CD1", "CD2"]),
    "MET": ("[CH2:10][CH2:11][S:12][CH3:13]", ["CB", "CG", "SD", "CE"]),
    "CYS": ("[CH2:10][SH:11]", ["CB", "SG"]),
}
# (residue, chain, number, key atom, kind of contact the key atom seeks); polar ones first
POCKET = [
    ("ASP", "A", 32, "OD1", "acc"), ("LYS", "A", 57, "NZ", "don"), ("ARG", "B", 14, "NH1", "don"),
    ("SER", "A", 88, "OG", "both"), ("HIS", "B", 45, "NE2", "acc"), ("TYR", "A", 113, "OH", "both"),
    ("ASN", "B", 71, "ND2", "don"), ("GLU", "B", 99, "OE1", "acc"), ("TRP", "A", 146, "NE1", "don"),
    ("PHE", "B", 128, "CZ", "apolar"), ("LEU", "A", 190, "CD1", "apolar"),
    ("MET", "B", 160, "CE", "apolar"), ("CYS", "A", 215, "SG", "apolar"),
]
ZN = ("ZN", "A", 301)
N_TRIALS = 4000
# minimum distances by category: 0 N/O, 1 other heavy, 2 H on N/O, 3 H on C (or S)
MIN_D = np.array([[2.7, 3.2, 1.75, 2.4],
                  [3.2, 3.4, 2.5, 2.5],
                  [1.75, 2.5, 2.0, 2.0],
                  [2.4, 2.5, 2.0, 2.0]])
CONTACT = 4.5
ZN_MIN = 2.8

TOL = 1e-4


# ----------------------------------------------------------------------------------------------
# RDKit helpers
# ----------------------------------------------------------------------------------------------
def embed(smiles, seed):
    from rdkit import Chem
    from rdkit.Chem import AllChem
    mol = Chem.AddHs(Chem.MolFromSmiles(smiles))
    ps = AllChem.ETKDGv3()
    ps.randomSeed = seed
    ps.numThreads = 1
    if AllChem.EmbedMolecule(mol, ps) != 0:
        raise RuntimeError("embedding failed: " + smiles)
    AllChem.MMFFOptimizeMolecule(mol, maxIters=5000)
    return mol


def coords(mol):
    c = mol.GetConformer()
    return np.array([list(c.GetAtomPosition(i)) for i in range(mol.GetNumAtoms())])


def set_coords(mol, X):
    from rdkit.Geometry import Point3D
    c = mol.GetConformer()
    for i, p in enumerate(X):
        c.SetAtomPosition(i, Point3D(*map(float, p)))


def categories(mol):
    cat = []
    for a in mol.GetAtoms():
        z = a.GetAtomicNum()
        if z == 1:
            nb = a.GetNeighbors()[0].GetAtomicNum()
            cat.append(2 if nb in (7, 8) else 3)
        else:
            cat.append(0 if z in (7, 8) else 1)
    return np.array(cat)


def canonical_frame(mol):
    """Heavy-atom centroid to the origin, principal axes to x, y, z (proper rotation)."""
    X = coords(mol)
    heavy = np.array([a.GetAtomicNum() > 1 for a in mol.GetAtoms()])
    c = X[heavy].mean(axis=0)
    Y = X - c
    w, V = np.linalg.eigh(np.cov(Y[heavy].T))
    V = V[:, ::-1]
    for k in range(2):
        if np.sum((Y[heavy] @ V[:, k]) ** 3) < 0:
            V[:, k] = -V[:, k]
    V[:, 2] = np.cross(V[:, 0], V[:, 1])
    # 3 decimals now, so that meeko (rounds the double) and Open Babel (reads the SDF's 4
    # decimals, then rounds) write the same coordinates
    set_coords(mol, np.round(Y @ V, 3))


def unit(v):
    return v / np.linalg.norm(v)


def rot_from_to(a, b):
    a, b = unit(a), unit(b)
    v = np.cross(a, b)
    c = float(np.dot(a, b))
    if np.linalg.norm(v) < 1e-9:
        if c > 0:
            return np.eye(3)
        p = unit(np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0]))
        return mr.rotation_matrix(p, 180.0)
    return mr.rotation_matrix(v, math.degrees(math.atan2(np.linalg.norm(v), c)))


def pair_ok(XA, CA, XB, CB):
    d = np.sqrt(((XA[:, None, :] - XB[None, :, :]) ** 2).sum(-1))
    return bool(np.all(d >= MIN_D[CA[:, None], CB[None, :]]))


# ----------------------------------------------------------------------------------------------
# Receptor
# ----------------------------------------------------------------------------------------------
def build_fragment(res, seed):
    from rdkit import Chem
    side, names = SIDE[res]
    mol = embed(BACKBONE.format(side=side), seed)
    info = []  # (resname, atom name) per atom
    for a in mol.GetAtoms():
        m = a.GetAtomMapNum()
        if a.GetAtomicNum() == 1:
            info.append(None)
        elif m in BB_NAMES:
            r, n = BB_NAMES[m]
            info.append((r or res, n))
        else:
            info.append((res, names[m - 10]))
    # hydrogens: H + parent name without its element letter (+ counter when several)
    for a in mol.GetAtoms():
        if a.GetAtomicNum() == 1:
            continue
        hs = [n.GetIdx() for n in a.GetNeighbors() if n.GetAtomicNum() == 1]
        r, pn = info[a.GetIdx()]
        stem = "H" + pn[1:] if pn not in ("N",) else "H"
        if r == "NME" and pn == "N":
            stem = "H"
        for k, h in enumerate(hs):
            info[h] = (r, stem + (str(k + 1) if len(hs) > 1 else ""))
    for r in {i[0] for i in info}:
        nm = [i[1] for i in info if i[0] == r]
        assert len(nm) == len(set(nm)) and all(len(n) <= 4 for n in nm), (res, r, nm)
    for a in mol.GetAtoms():
        a.SetAtomMapNum(0)
    return mol, info


def place_pocket(ligs):
    """Seeded placement of the capped residues around the three ligands (all at the origin)."""
    rng = np.random.default_rng(RECEPTOR_SEED)
    LX = np.vstack([coords(m) for _, m in ligs])
    LC = np.concatenate([categories(m) for _, m in ligs])
    heavy = LC < 2
    HX = LX[heavy]
    owner = np.concatenate([[k] * m.GetNumAtoms() for k, (_, m) in enumerate(ligs)])[heavy]
    acc, don = [], []
    for _, m in ligs:
        for a in m.GetAtoms():
            if a.GetAtomicNum() == 1:
                continue
            z, nh = a.GetAtomicNum(), a.GetTotalNumHs(includeNeighbors=True)
            acc.append(z == 8 or (z == 7 and nh == 0 and a.GetFormalCharge() == 0 and a.GetIsAromatic()))
            don.append(z in (7, 8) and nh > 0)
    acc, don = np.array(acc), np.array(don)
    apolar = LC[heavy] == 1
    centre = HX.mean(axis=0)
    cover = np.zeros(len(HX))
    placed = []  # (mol, info, chain, resnum)
    RX = np.zeros((0, 3))
    RC = np.zeros(0, dtype=int)
    for k, (res, chain, num, key, kind) in enumerate(POCKET):
        mol, info = build_fragment(res, RECEPTOR_SEED + 101 * k)
        X0 = coords(mol)
        C0 = categories(mol)
        fh = C0 < 2
        ki = next(i for i, t in enumerate(info) if t == (res, key))
        body = X0[fh].mean(axis=0) - X0[ki]
        targets = {"acc": np.where(don)[0], "don": np.where(acc)[0],
                   "both": np.where(acc | don)[0], "apolar": np.where(apolar)[0]}[kind]
        best = None
        for trial in range(2 * N_TRIALS):
            if trial == N_TRIALS:
                if best is not None:
                    break
                print("  (%s: no place with its key atom at a %s partner; any ligand atom now)" % (res, kind))
                targets, kind = np.arange(len(HX)), "apolar"
            d0 = rng.uniform(3.6, 4.2) if kind == "apolar" else rng.uniform(2.8, 3.2)
            t = HX[int(rng.choice(targets))]
            u = unit(unit(t - centre + 1e-6) + 0.8 * unit(rng.normal(size=3)))
            R = mr.rotation_matrix(u, float(rng.uniform(0.0, 360.0))) @ rot_from_to(body, u)
            X = (X0 - X0[ki]) @ R.T + t + d0 * u
            if not pair_ok(X, C0, LX, LC) or (len(RX) and not pair_ok(X, C0, RX, RC)):
                continue
            d = np.sqrt(((HX[:, None, :] - X[fh][None, :, :]) ** 2).sum(-1)).min(axis=1)
            touch = d < CONTACT
            score = float(np.sum(touch / (1.0 + cover)))
            if best is None or score > best[0] + 1e-12:
                best = (score, X, touch)
        if best is None:
            raise RuntimeError("no place found for " + res)
        set_coords(mol, best[1])
        cover += best[2]
        placed.append((mol, info, chain, num))
        RX = np.vstack([RX, best[1]])
        RC = np.concatenate([RC, C0])
        print("  placed %s %s%d: touches %d ligand heavy atoms (lig1/2/3: %s)" % (
            res, chain, num, int(best[2].sum()),
            "/".join(str(int(best[2][owner == j].sum())) for j in range(len(ligs)))))
    # Zn: on a 0.25 A grid, >= ZN_MIN from every ligand atom and receptor heavy atom, >= 2.2 A
    # from receptor hydrogens; nearest to all three ligands (sum of the nearest heavy distances)
    lo, hi = HX.min(axis=0) - 5.0, HX.max(axis=0) + 5.0
    g = [np.arange(lo[i], hi[i], 0.25) for i in range(3)]
    G = np.stack(np.meshgrid(*g, indexing="ij"), -1).reshape(-1, 3)
    dl = np.sqrt(((G[:, None, :] - LX[None]) ** 2).sum(-1)).min(axis=1)
    rh = RC < 2
    dr = np.sqrt(((G[:, None, :] - RX[rh][None]) ** 2).sum(-1)).min(axis=1)
    drh = np.sqrt(((G[:, None, :] - RX[~rh][None]) ** 2).sum(-1)).min(axis=1)
    ok = (dl >= ZN_MIN) & (dr >= ZN_MIN) & (drh >= 2.2)
    per = np.stack([np.sqrt(((G[:, None, :] - HX[owner == j][None]) ** 2).sum(-1)).min(axis=1)
                    for j in range(len(ligs))], 1)
    cost = np.where(ok, np.sum(np.maximum(per, ZN_MIN), axis=1), np.inf)
    zi = int(np.argmin(cost))
    zn = np.round(G[zi], 3)
    print("  Zn at %s: nearest heavy atom of lig1/2/3 %s A" % (zn.tolist(), np.round(per[zi], 2).tolist()))
    return placed, zn


def write_receptor_pdbqt(placed, zn, work, out_path):
    """Protein part through Open Babel (run in the work folder so that the REMARK Name lines
    hold the bare file name), then the Zn line appended in the same column layout: Open Babel's
    Gasteiger model has no zinc parameters (with the ion in, every charge is written as 0.000)
    and its rigid writer writes ATOM for HETATM input."""
    write_receptor_pdb(placed, os.path.join(work, "receptor.pdb"))
    here = os.getcwd()
    out_abs = os.path.abspath(out_path)
    os.chdir(work)
    try:
        ok = mr.ob_to_pdbqt("receptor.pdb", "pdb", out_abs, add_h=False, rigid=True)
    finally:
        os.chdir(here)
    if not ok:
        raise SystemExit("FAIL: Open Babel Gasteiger charges failed for the receptor")
    text = open(out_abs).read()
    n = sum(1 for l in text.splitlines() if l.startswith(("ATOM  ", "HETATM")))
    text += ("HETATM%5d ZN    ZN %1s%4d    %8.3f%8.3f%8.3f  0.00  0.00    +2.000 Zn\n"
             % (n + 1, ZN[1], ZN[2], zn[0], zn[1], zn[2]))
    with open(out_abs, "w") as f:
        f.write(text)


def write_receptor_pdb(placed, path):
    rows = []
    for mol, info, chain, num in placed:
        X = coords(mol)
        res = next(i[0] for i in info if i[0] not in ("ACE", "NME"))
        off = {"ACE": -1, res: 0, "NME": 1}
        for a in mol.GetAtoms():
            r, n = info[a.GetIdx()]
            el = a.GetSymbol()
            q = a.GetFormalCharge()
            rows.append((chain, num + off[r], 0 if el != "H" else 1, a.GetIdx(), r, n, el, q, X[a.GetIdx()]))
    rows.sort(key=lambda t: (t[0], t[1], t[2], t[3]))
    lines = []
    serial = 0
    prev_chain = None
    for chain, num, _h, _i, r, n, el, q, x in rows:
        if prev_chain is not None and chain != prev_chain:
            serial += 1
            lines.append("TER   %5d      %3s %1s%4d" % (serial, last[0], prev_chain, last[1]))
        serial += 1
        nm = n if len(n) == 4 else " " + n
        qs = "" if q == 0 else "%d%s" % (abs(q), "+" if q > 0 else "-")
        lines.append("ATOM  %5d %-4s %3s %1s%4d    %8.3f%8.3f%8.3f  1.00  0.00          %2s%2s"
                     % (serial, nm, r, chain, num, x[0], x[1], x[2], el.upper(), qs))
        prev_chain, last = chain, (r, num)
    serial += 1
    lines.append("TER   %5d      %3s %1s%4d" % (serial, last[0], prev_chain, last[1]))
    lines.append("END")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


# ----------------------------------------------------------------------------------------------
# Ligand files
# ----------------------------------------------------------------------------------------------
def meeko_pdbqt(mol):
    from meeko import MoleculePreparation, PDBQTWriterLegacy
    setups = MoleculePreparation().prepare(mol)
    s, ok, err = PDBQTWriterLegacy.write_string(setups[0])
    if not ok:
        raise RuntimeError("meeko: " + err)
    return s


def obabel_pdbqt(mol, name, work):
    from rdkit import Chem
    sdf = os.path.join(work, name + ".sdf")
    out = os.path.join(work, name + "_ob.pdbqt")
    mol.SetProp("_Name", name)
    Chem.MolToMolFile(mol, sdf)
    if not mr.ob_to_pdbqt(sdf, "sdf", out, add_h=False, rigid=False):
        raise RuntimeError("Open Babel Gasteiger charges failed for " + name)
    return open(out).read()


def split_models(text):
    models, cur = [], None
    for l in text.splitlines():
        if l.startswith("MODEL"):
            cur = []
        elif l.startswith("ENDMDL"):
            models.append("\n".join(cur) + "\n")
            cur = None
        elif cur is not None:
            cur.append(l)
    return models


def shifted(text, s):
    out = []
    for l in text.splitlines():
        if l.startswith("ATOM  ") or l.startswith("HETATM"):
            x = [round(float(l[30 + 8 * k:38 + 8 * k]) + s[k], 3) for k in range(3)]
            l = l[:30] + "".join("%8.3f" % v for v in x) + l[54:]
        out.append(l)
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------------------------
# Scoring and checks
# ----------------------------------------------------------------------------------------------
class Receptor:
    def __init__(self, path):
        self.path = path
        self.atoms = mr.parse_receptor_pdbqt(open(path).read())
        self.bonds = mr.assign_bonds_rigid(self.atoms)
        self.xs = mr.assign_xs(self.atoms, self.bonds)
        self.heavy = [i for i, x in enumerate(self.xs) if x is not None]
        self.X = np.array([self.atoms[i]["xyz"] for i in self.heavy])
        self.XS = [self.xs[i] for i in self.heavy]


def score_file(key, text, model, rec, shifts, worst, require_terms):
    tree = mr.LigandTree(text)
    la = tree.atoms
    bonds = mr.assign_bonds_ligand(la, tree.mobility)
    xs = mr.assign_xs(la, bonds)
    pairs = mr.intra_pairs(tree, bonds, xs)
    ntors = mr.num_tors(la, bonds)
    hv = [i for i, a in enumerate(la) if not mr.is_hydrogen(a)]
    to_h = {v: n for n, v in enumerate(hv)}
    hpairs = [(to_h[i], to_h[j]) for i, j in pairs]
    hxs = [xs[i] for i in hv]
    texts = [shifted(text, s) if any(s) else text for s in shifts]
    allx = np.vstack([[mr.read_pose_pdbqt(t)[a["serial"]] for a in la] for t in texts])
    center = np.round(allx.mean(axis=0), 3)
    size = np.ceil(2 * (np.max(np.abs(allx - center), axis=0) + mr.BOX_MARGIN))
    poses = [{"shift": list(s)} for s in shifts]
    for sf, terms, wdef in (("vina", mr.VINA_TERMS, mr.VINA_WEIGHTS),
                            ("vinardo", mr.VINARDO_TERMS, mr.VINARDO_WEIGHTS)):
        full = mr.score_all(sf, wdef, rec.path, texts, center.tolist(), size.tolist())
        raw = {}
        for ti, t in enumerate(terms):
            w = [0.0] * (len(terms) + 2)
            w[ti] = -1.0
            raw[t] = mr.score_all(sf, w, rec.path, texts, center.tolist(), size.tolist())
        for pi, t in enumerate(texts):
            seen = mr.read_pose_pdbqt(t)
            LX = np.array([seen[la[i]["serial"]] for i in hv])
            f = full[pi]
            poses[pi][sf] = {"total": f[0], "inter": f[1], "intra": f[5]}
            mine = mr.reimpl_score(sf, wdef, rec.X, rec.XS, LX, hxs, hpairs, ntors)
            worst[sf]["inter"] = max(worst[sf]["inter"], abs(mine["inter"] - f[1]))
            worst[sf]["intra"] = max(worst[sf]["intra"], abs(mine["intra"] - f[5]))
            worst[sf]["total"] = max(worst[sf]["total"], abs(mine["total"] - f[0]))
            if abs(f[0]) > 1e-9:
                implied = (f[1] / f[0] - 1.0) / wdef[-1]
                worst[sf]["num_tors"] = max(worst[sf]["num_tors"], abs(implied - ntors))
            for ti, tn in enumerate(terms):
                w = [0.0] * (len(terms) + 2)
                w[ti] = -1.0
                m = mr.reimpl_score(sf, w, rec.X, rec.XS, LX, hxs, hpairs, 0.0)
                r = raw[tn][pi]
                worst[sf]["terms"] = max(worst[sf]["terms"], abs(m["inter"] - r[1]), abs(m["intra"] - r[5]))
                if require_terms and pi == 0 and abs(r[1]) < 1e-6:
                    raise SystemExit("FAIL: %s %s term %s is zero at shift 0" % (key, sf, tn))
    atoms = sorted(({"serial": la[i]["serial"], "ad": la[i]["ad_text"], "xs": xs[i]} for i in hv),
                   key=lambda d: d["serial"])
    return {"model": model, "torsdof": tree.torsdof, "num_tors": ntors, "atoms": atoms, "poses": poses}


def seeded_shifts(name):
    rng = np.random.default_rng(zlib.crc32((SHIFT_SEED + name).encode()))
    out = [[0.0, 0.0, 0.0]]
    for _ in range(N_SHIFTS):
        v = unit(rng.normal(size=3)) * rng.uniform(0.3, 1.0)
        out.append([round(float(c), 3) for c in v])
    return out


# ----------------------------------------------------------------------------------------------
# JSON (sorted keys, 6 decimals; a dict or list of scalars stays on one line)
# ----------------------------------------------------------------------------------------------
def _flat(v):
    if isinstance(v, dict):
        return all(not isinstance(e, (list, tuple, dict)) for e in v.values())
    return isinstance(v, (list, tuple)) and all(not isinstance(e, (list, tuple, dict)) for e in v)


def dumps(obj, indent=0):
    pad = " " * indent
    if isinstance(obj, dict):
        keys = sorted(obj, key=str)
        if _flat(obj):
            return "{" + ", ".join("%s: %s" % (json.dumps(str(k)), mr._scalar(obj[k])) for k in keys) + "}"
        return "{\n" + ",\n".join("%s  %s: %s" % (pad, json.dumps(str(k)), dumps(obj[k], indent + 2))
                                  for k in keys) + "\n" + pad + "}"
    if isinstance(obj, (list, tuple)):
        if _flat(obj):
            return "[" + ", ".join(mr._scalar(e) for e in obj) + "]"
        return "[\n" + ",\n".join(pad + "  " + dumps(e, indent + 2) for e in obj) + "\n" + pad + "]"
    return mr._scalar(obj)


# ----------------------------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="tests/data/pdbqt")
    ap.add_argument("--keep", action="store_true", help="keep the temporary work directory")
    args = ap.parse_args()
    import vina
    import rdkit
    from openbabel import openbabel as ob
    os.makedirs(args.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="make_pdbqt_")

    print("== ligands")
    ligs = []
    for k, (name, smi) in enumerate(LIGANDS):
        m = embed(smi, LIGAND_SEED + k)
        canonical_frame(m)
        ligs.append((name, m))
    print("== pocket")
    placed, zn = place_pocket(ligs)
    rec_path = os.path.join(args.out, "receptor.pdbqt")
    write_receptor_pdbqt(placed, zn, work, rec_path)
    rec = Receptor(rec_path)

    files = []
    for name, m in ligs:
        for tool, text in (("meeko", meeko_pdbqt(m)), ("obabel", obabel_pdbqt(m, name, work))):
            fn = "%s_%s.pdbqt" % (name, tool)
            with open(os.path.join(args.out, fn), "w") as f:
                f.write(text)
            files.append((fn, name, text))

    print("== docking")
    lig1 = open(os.path.join(args.out, "lig1_meeko.pdbqt")).read()
    tree = mr.LigandTree(lig1)
    X = np.array([a["xyz"] for a in tree.atoms if not mr.is_hydrogen(a)])
    dc = np.round(X.mean(axis=0), 3)
    dsize = np.ceil(np.ptp(X, axis=0) + 8.0)
    v = vina.Vina(sf_name="vina", seed=DOCK_SEED, cpu=1, verbosity=0)
    v.set_receptor(rec_path)
    v.set_ligand_from_string(lig1)
    v.compute_vina_maps(center=dc.tolist(), box_size=dsize.tolist())
    v.dock(exhaustiveness=2, n_poses=3)
    dock_path = os.path.join(args.out, "dock_out.pdbqt")
    v.write_poses(dock_path, n_poses=3, energy_range=100.0, overwrite=True)
    dock_text = open(dock_path).read()
    models = split_models(dock_text)
    if len(models) != 3:
        raise SystemExit("FAIL: docking wrote %d models" % len(models))

    print("== scoring")
    worst = {sf: dict(inter=0.0, intra=0.0, total=0.0, terms=0.0, num_tors=0.0) for sf in ("vina", "vinardo")}
    out = {"generator": "tests/reference/vina/make_pdbqt.py",
           "vina": vina.__version__,
           "meeko": mr._dist_version("meeko"),
           "openbabel": mr._dist_version("openbabel-wheel"),
           "openbabel_release": ob.OBReleaseVersion(),
           "rdkit": rdkit.__version__,
           "receptor": {"file": "receptor.pdbqt",
                        "atoms": [{"index": i, "serial": rec.atoms[i]["serial"], "chain": rec.atoms[i]["chain"],
                                   "resname": rec.atoms[i]["resname"], "resnum": int(rec.atoms[i]["resnum"]),
                                   "name": rec.atoms[i]["name"], "ad": rec.atoms[i]["ad_text"],
                                   "xs": rec.xs[i]} for i in rec.heavy]},
           "ligands": {}}
    for fn, name, text in files:
        e = score_file(fn, text, 1, rec, seeded_shifts(name), worst, True)
        e["smiles"] = dict(LIGANDS)[name]
        out["ligands"][fn] = e
    for k, t in enumerate(models):
        key = "dock_out.pdbqt#%d" % (k + 1)
        e = score_file(key, t, k + 1, rec, [[0.0, 0.0, 0.0]], worst, False)
        rem = next(l for l in t.splitlines() if l.startswith("REMARK VINA RESULT"))
        e["vina_result"] = [float(x) for x in rem.split()[3:6]]
        out["ligands"][key] = e

    # ---- report and checks -------------------------------------------------------------------
    rl = np.array([a["xyz"] for a in rec.atoms])
    for key, e in sorted(out["ligands"].items()):
        p = e["poses"][0]
        print("%-22s torsdof %2d num_tors %4.1f  vina %9.5f %9.5f %9.5f  vinardo %9.5f %9.5f %9.5f" % (
            key, e["torsdof"], e["num_tors"], p["vina"]["total"], p["vina"]["inter"], p["vina"]["intra"],
            p["vinardo"]["total"], p["vinardo"]["inter"], p["vinardo"]["intra"]))
    for fn, name, text in files:
        la = mr.LigandTree(text).atoms
        LX = np.array([a["xyz"] for a in la if not mr.is_hydrogen(a)])
        d = np.sqrt(((LX[:, None] - rec.X[None]) ** 2).sum(-1))
        zi = [n for n, i in enumerate(rec.heavy) if rec.atoms[i]["ad"] == "Zn"][0]
        LA = np.array([a["xyz"] for a in la])
        dz = np.sqrt(((LA - rec.X[zi]) ** 2).sum(-1))
        print("  %-18s closest heavy pair %.2f A, receptor heavy atoms within 4 A: %d, Zn nearest %.2f A"
              % (fn, d.min(), int((d.min(axis=0) < 4.0).sum()), dz.min()))
        if d.min() < 2.6 or dz.min() < ZN_MIN or dz.min() > 5.0:
            raise SystemExit("FAIL: %s contact distances out of range" % fn)
    print("largest |reimplementation - Vina|:")
    bad = False
    for sf, w in worst.items():
        print("  %-8s %s" % (sf, ", ".join("%s %.2e" % kv for kv in w.items())))
        bad |= any(x > TOL for x in w.values())
    if bad:
        raise SystemExit("FAIL: the transcription's types/scores disagree with Vina by more than %g" % TOL)

    with open(os.path.join(args.out, "values.json"), "w") as f:
        f.write(dumps(out) + "\n")
    if args.keep:
        print("kept", work)
    else:
        shutil.rmtree(work, ignore_errors=True)
    for fn in sorted(os.listdir(args.out)):
        print("  %-20s %7d bytes" % (fn, os.path.getsize(os.path.join(args.out, fn))))


if __name__ == "__main__":
    main()
