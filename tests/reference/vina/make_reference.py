#!/usr/bin/env python3
"""Reference values from AutoDock Vina 1.2 for bump's Vina/Vinardo scoring.

Run from the repository root (Python 3.11, packages pinned in requirements.txt):

    python tests/reference/vina/make_reference.py [--pdb-dir ../shared/pdb] [--out tests/reference/vina/values.json]

What it does, per protein-ligand complex of the shared structure folder:

* prepares, in a temporary directory only, a receptor PDBQT (polymer ATOM records of the first
  model, first alternate conformer, all HETATM groups -- waters, ions, cofactors, the ligand --
  removed; Open Babel adds hydrogens, computes Gasteiger charges and writes a rigid PDBQT with
  non-polar hydrogens merged) and a ligand PDBQT (Open Babel, torsion tree, from an SDF built
  with RDKit: the shared SDF where there is one, else the PDB HETATM residue with bond orders
  taken from a SMILES template; missing hydrogens added by RDKit with coordinates);
* scores the crystal pose and seeded rigid perturbations of it with vina.Vina(sf_name='vina')
  and sf_name='vinardo', total and term by term (set_weights with one non-zero weight);
* records every ligand heavy atom and every receptor heavy atom within 8 A of any scored pose,
  with coordinates, PDBQT (AutoDock) type, the XS type Vina assigns and the Gasteiger charge
  Open Babel wrote;
* runs Vina's local optimisation from a few perturbed poses;
* re-computes everything with an independent numpy transcription of docs/vina-scoring.md and
  records the largest disagreement with Vina (the specification's self-check);
* writes values.json deterministically (sorted keys, floats with 6 decimals).

Nothing from the shared folder is copied into the repository; derived files live in a
temporary directory that is deleted at the end (use --keep to keep it for inspection).
"""
import argparse
import hashlib
import json
import math
import os
import platform
import shutil
import sys
import tempfile
import zlib

import numpy as np

# ----------------------------------------------------------------------------------------------
# The complexes. "ligand" selects the HETATM residue (name, chain; the first residue matching);
# "sdf" (optional) is a shared SDF holding the same pose with bond orders; "template" is a
# SMILES used to assign bond orders to a ligand read from PDB/mmCIF coordinates (topology
# only: hydrogens, charges and stereo in the SMILES are what the ligand gets).
# ----------------------------------------------------------------------------------------------
COMPLEXES = [
    dict(id="6xg5_TOP", receptor="6xg5_tmp_prepared.pdb", ligand=("TOP", "X"),
         sdf="trimethoprim_top_6xg5pose.sdf"),
    dict(id="3ptb_BEN", receptor="3ptb.pdb", ligand=("BEN", "A"), sdf="benzamidine_3ptb.sdf"),
    dict(id="1s3v_TQD", receptor="1s3v_protein.pdb", ligand=None, sdf="1s3v_ligand_tqd.sdf"),
    dict(id="4dfr_MTX", receptor="4dfr.pdb", ligand=("MTX", "A"),
         template="Nc1nc(N)c2nc(CN(C)c3ccc(cc3)C(=O)NC(CCC(=O)O)C(=O)O)cnc2n1"),
    dict(id="1u72_MTX", receptor="1u72.pdb", ligand=("MTX", "A"),
         template="Nc1nc(N)c2nc(CN(C)c3ccc(cc3)C(=O)NC(CCC(=O)O)C(=O)O)cnc2n1"),
    dict(id="3nzd_D2Q", receptor="3nzd.cif", ligand=("D2Q", "A"),
         template="CCOC(=O)CCCCOc1ccc(OC)cc1Cc1cnc2nc(N)nc(N)c2c1C"),
    dict(id="1hvr_XK2", receptor="1hvr.pdb", ligand=("XK2", "A"),
         template="O=C1N(Cc2ccc3ccccc3c2)C(Cc2ccccc2)C(O)C(O)C(Cc2ccccc2)N1Cc1ccc2ccccc2c1"),
    dict(id="1rx1_NAP", receptor="1rx1.pdb", ligand=("NAP", "A"),
         template=("NC(=O)c1ccc[n+](c1)C1OC(COP(=O)(O)OP(=O)(O)OCC2OC(C(OP(=O)(O)O)C2O)"
                   "n2cnc3c(N)ncnc32)C(O)C1O")),
]

N_SMALL = 8            # small perturbations per complex
SMALL_MAX_SHIFT = 1.5  # A
SMALL_MAX_ANGLE = 30.0 # degrees
LARGE = [(3.0, 40.0), (4.0, 60.0)]  # (shift A, angle deg) of the larger perturbations
OPTIMIZE_POSES = ["small_1", "small_2", "large_1"]
RECEPTOR_SHELL = 8.0   # A, receptor heavy atoms recorded around any scored pose
SCORE_SPACING = 1.0    # grid spacing used only to satisfy score()'s box check (see docs)
OPT_SPACING = 0.375    # Vina's default spacing; optimize() runs on these grid maps
BOX_MARGIN = 6.0       # A added around every scored pose when sizing the box

VINA_WEIGHTS = (-0.035579, -0.005156, 0.840245, -0.035069, -0.587439, 50.0, 0.05846)
VINA_TERMS = ["gauss1", "gauss2", "repulsion", "hydrophobic", "hydrogen"]
VINARDO_WEIGHTS = (-0.045, 0.8, -0.035, -0.6, 50.0, 0.05846)
VINARDO_TERMS = ["gauss", "repulsion", "hydrophobic", "hydrogen"]
SCORE_COLUMNS = ["total", "lig_inter", "flex_inter", "other_inter", "flex_intra", "lig_intra",
                 "torsions", "lig_intra_best_pose"]


# ==============================================================================================
# Small helpers
# ==============================================================================================
def fmt8(x):
    """The most precise fixed-point text of x that fits PDBQT's 8-character coordinate field.
    Vina parses columns 31-38/39-46/47-54 with boost::lexical_cast<double>, so extra decimals
    are read exactly; the value Vina sees is float(fmt8(x))."""
    for d in (6, 5, 4, 3):
        s = "%8.*f" % (d, x)
        if len(s) == 8:
            return s
    raise ValueError("coordinate %r does not fit a PDBQT field" % x)


def rotation_matrix(axis, angle_deg):
    k = np.asarray(axis, float)
    k = k / np.linalg.norm(k)
    th = math.radians(angle_deg)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) * math.cos(th) + math.sin(th) * K + (1 - math.cos(th)) * np.outer(k, k)


def apply_transform(xyz, centroid, axis, angle_deg, shift):
    R = rotation_matrix(axis, angle_deg)
    c = np.asarray(centroid, float)
    return (np.asarray(xyz, float) - c) @ R.T + c + np.asarray(shift, float)


# ==============================================================================================
# Input preparation
# ==============================================================================================
def load_structure(path):
    import gemmi
    st = gemmi.read_structure(path)
    st.setup_entities()
    st.remove_alternative_conformations()  # keeps the first conformer (blank or 'A')
    while len(st) > 1:
        del st[1]
    return st


def write_receptor_pdb(st, out_pdb):
    """Polymer atoms only (het_flag 'A' = ATOM records); every HETATM group is dropped."""
    import gemmi
    ns = gemmi.Structure()
    ns.cell = st.cell
    ns.spacegroup_hm = st.spacegroup_hm
    model = gemmi.Model("1")
    for ch in st[0]:
        nc = gemmi.Chain(ch.name)
        for res in ch:
            if res.het_flag == "A":
                nc.add_residue(res)
        if len(nc):
            model.add_chain(nc)
    ns.add_model(model)
    ns.write_pdb(out_pdb, gemmi.PdbWriteOptions(minimal=True))
    return sum(len(r) for ch in model for r in ch)


def ligand_residue(st, name, chain):
    for ch in st[0]:
        if ch.name != chain:
            continue
        for res in ch:
            if res.name == name:
                return res
    raise RuntimeError("ligand %s chain %s not found" % (name, chain))


def ligand_from_pdb_residue(res, template_smiles):
    """RDKit molecule of a PDB residue: heavy atoms at their deposited coordinates, bond orders
    from the SMILES template, hydrogens added by RDKit with coordinates."""
    from rdkit import Chem
    from rdkit.Chem import AllChem
    lines = []
    for i, a in enumerate(res):
        if a.element.name in ("H", "D"):
            continue
        lines.append("HETATM%5d %-4s %3s A   1    %8.3f%8.3f%8.3f  1.00  0.00          %2s"
                     % (i + 1, a.name if len(a.name) == 4 else " " + a.name, res.name,
                        a.pos.x, a.pos.y, a.pos.z, a.element.name.upper()))
    block = "\n".join(lines) + "\nEND\n"
    raw = Chem.MolFromPDBBlock(block, removeHs=False, sanitize=False, proximityBonding=True)
    tmpl = Chem.MolFromSmiles(template_smiles)
    mol = AllChem.AssignBondOrdersFromTemplate(tmpl, raw)
    Chem.SanitizeMol(mol)
    names = [a.name for a in res if a.element.name not in ("H", "D")]
    serials = [a.serial for a in res if a.element.name not in ("H", "D")]
    orig = [(a.pos.x, a.pos.y, a.pos.z) for a in res if a.element.name not in ("H", "D")]
    return mol, names, serials, orig


def ligand_from_sdf(path):
    from rdkit import Chem
    mol = Chem.MolFromMolFile(path, removeHs=False)
    conf = mol.GetConformer()
    orig = [tuple(conf.GetAtomPosition(a.GetIdx())) for a in mol.GetAtoms() if a.GetAtomicNum() > 1]
    idx = [a.GetIdx() for a in mol.GetAtoms() if a.GetAtomicNum() > 1]
    return mol, idx, orig


def add_h_with_coords(mol):
    from rdkit import Chem
    if all(a.GetTotalNumHs() == 0 for a in mol.GetAtoms()):
        return mol, 0
    n_before = mol.GetNumAtoms()
    molh = Chem.AddHs(mol, addCoords=True)
    return molh, molh.GetNumAtoms() - n_before


# ==============================================================================================
# PDBQT parsing (Vina semantics: parse_pdbqt.cpp)
# ==============================================================================================
AD_TYPES = ["C", "A", "N", "O", "P", "S", "H", "F", "I", "NA", "OA", "SA", "HD", "Mg", "Mn", "Zn",
            "Ca", "Fe", "Cl", "Br", "Si", "At", "G0", "G1", "G2", "G3", "CG0", "CG1", "CG2", "CG3", "W"]
AD_COVALENT = {"C": 0.77, "A": 0.77, "N": 0.75, "O": 0.73, "P": 1.06, "S": 1.02, "H": 0.37,
               "F": 0.71, "I": 1.33, "NA": 0.75, "OA": 0.73, "SA": 1.02, "HD": 0.37, "Mg": 1.30,
               "Mn": 1.39, "Zn": 1.31, "Ca": 1.74, "Fe": 1.25, "Cl": 0.99, "Br": 1.14, "Si": 1.11,
               "At": 1.44, "G0": 0.77, "G1": 0.77, "G2": 0.77, "G3": 0.77, "CG0": 0.77,
               "CG1": 0.77, "CG2": 0.77, "CG3": 0.77, "W": 0.0}
MAX_COVALENT = max(AD_COVALENT.values())  # 1.74 (Ca)
NON_AD_METALS = {"Cu", "Fe", "Na", "K", "Hg", "Co", "U", "Cd", "Ni"}
METAL_COVALENT = 1.75
AD_ELEMENT = {"C": "C", "A": "C", "N": "N", "NA": "N", "O": "O", "OA": "O", "S": "S", "SA": "S",
              "P": "P", "H": "H", "HD": "H", "F": "F", "I": "I", "Cl": "Cl", "Br": "Br",
              "Si": "Si", "At": "At", "Mg": "Met", "Mn": "Met", "Zn": "Met", "Ca": "Met",
              "Fe": "Met"}
XS_NAMES = ["C_H", "C_P", "N_P", "N_D", "N_A", "N_DA", "O_P", "O_D", "O_A", "O_DA", "S_P", "P_P",
            "F_H", "Cl_H", "Br_H", "I_H", "Si", "At", "Met_D"]
XS_RADIUS_VINA = {"C_H": 1.9, "C_P": 1.9, "N_P": 1.8, "N_D": 1.8, "N_A": 1.8, "N_DA": 1.8,
                  "O_P": 1.7, "O_D": 1.7, "O_A": 1.7, "O_DA": 1.7, "S_P": 2.0, "P_P": 2.1,
                  "F_H": 1.5, "Cl_H": 1.8, "Br_H": 2.0, "I_H": 2.2, "Si": 2.2, "At": 2.3,
                  "Met_D": 1.2}
XS_RADIUS_VINARDO = {"C_H": 2.0, "C_P": 2.0, "N_P": 1.7, "N_D": 1.7, "N_A": 1.7, "N_DA": 1.7,
                     "O_P": 1.6, "O_D": 1.6, "O_A": 1.6, "O_DA": 1.6, "S_P": 2.0, "P_P": 2.1,
                     "F_H": 1.5, "Cl_H": 1.8, "Br_H": 2.0, "I_H": 2.2, "Si": 2.2, "At": 2.3,
                     "Met_D": 1.2}
HYDROPHOBIC = {"C_H", "F_H", "Cl_H", "Br_H", "I_H"}
ACCEPTOR = {"N_A", "N_DA", "O_A", "O_DA"}
DONOR = {"N_D", "N_DA", "O_D", "O_DA", "Met_D"}


def parse_atom_line(line):
    name_t = line[77:79].strip() if len(line) >= 78 else ""
    t = "S" if name_t == "Se" else name_t
    q = line[68:76].strip()
    return dict(serial=int(line[6:11]), name=line[12:16].strip(), resname=line[17:20].strip(),
                chain=line[21:22], resnum=line[22:26].strip(), icode=line[26:27].strip(),
                xyz=(float(line[30:38]), float(line[38:46]), float(line[46:54])),
                q=float(q) if q else 0.0, ad=t, ad_text=name_t,
                metal=(name_t in NON_AD_METALS))


def parse_receptor_pdbqt(text):
    return [parse_atom_line(l) for l in text.splitlines()
            if l.startswith("ATOM  ") or l.startswith("HETATM")]


class LigandTree:
    """Vina's view of a ligand PDBQT: atoms in Vina's insertion order (postprocess_branch),
    the rigid 'nodes' (atom ranges), the mobility matrix and the torsion tree."""

    def __init__(self, text):
        self.lines = text.splitlines()
        root = {"atoms": [], "immobile": None, "children": {}}  # children: atom pos -> [struct]
        stack = [root]
        for l in self.lines:
            if l.startswith("ATOM  ") or l.startswith("HETATM"):
                a = parse_atom_line(l)
                cur = stack[-1]
                if cur.get("to") is not None and a["serial"] == cur["to"]:
                    cur["immobile"] = len(cur["atoms"])
                cur["atoms"].append({"a": a, "ps": []})
            elif l.startswith("BRANCH"):
                frm, to = map(int, l.split()[1:3])
                cur = stack[-1]
                for nd in cur["atoms"]:
                    if nd["a"]["serial"] == frm:
                        child = {"atoms": [], "immobile": None, "to": to, "from": frm}
                        nd["ps"].append(child)
                        stack.append(child)
                        break
                else:
                    raise RuntimeError("BRANCH atom %d not in enclosing fragment" % frm)
            elif l.startswith("ENDBRANCH"):
                stack.pop()
            elif l.startswith("TORSDOF"):
                self.torsdof = int(l.split()[1])
        self.atoms = []      # Vina order
        self.nodes = []      # (begin, end, axis_begin_index or None, axis_end_index or None, parent node)
        self.fixed = set()   # (i, j) i<j DISTANCE_FIXED
        self.rotor = set()   # (i, j) i<j DISTANCE_ROTOR
        self._post(root, None, None, None)

    def _insert(self, nd):
        idx = len(self.atoms)
        self.atoms.append(nd["a"])
        return idx

    def _post(self, p, axis_begin, axis_end, parent_node):
        begin = len(self.atoms)
        child_heads = []  # (struct, parent atom index)
        for i, nd in enumerate(p["atoms"]):
            if p["immobile"] is not None and i == p["immobile"] and axis_end is not None:
                mine = axis_end
            else:
                mine = self._insert(nd)
            for ps in nd["ps"]:
                ps_imm = ps["immobile"]
                head = self._insert(ps["atoms"][ps_imm])
                child_heads.append((ps, mine, head))
        end = len(self.atoms)
        node_id = len(self.nodes)
        self.nodes.append((begin, end, axis_begin, axis_end, parent_node))
        for ref in (axis_begin, axis_end):
            if ref is not None:
                for k in range(begin, end):
                    self.fixed.add((min(ref, k), max(ref, k)))
        if axis_begin is not None and axis_end is not None:
            key = (min(axis_begin, axis_end), max(axis_begin, axis_end))
            self.rotor.add(key)
        for i in range(begin, end):
            for j in range(i + 1, end):
                self.fixed.add((i, j))
        for ps, parent_atom, head in child_heads:
            essentially_empty = all(
                (ps["immobile"] is not None and k == ps["immobile"]) or False
                for k in range(len(ps["atoms"]))) and all(not nd["ps"] for nd in ps["atoms"])
            if not essentially_empty:
                self._post(ps, parent_atom, head, node_id)

    def mobility(self, i, j):
        if i == j:
            return "FIXED"
        key = (min(i, j), max(i, j))
        if key in self.rotor:
            return "ROTOR"
        if key in self.fixed:
            return "FIXED"
        return "VARIABLE"


# ==============================================================================================
# Vina model reconstruction (model.cpp: assign_bonds, assign_types, initialize_pairs)
# ==============================================================================================
def covalent_radius(a):
    if a["ad"] in AD_COVALENT:
        return AD_COVALENT[a["ad"]]
    if a["metal"]:
        return METAL_COVALENT
    raise RuntimeError("unknown type " + a["ad"])


def is_hydrogen(a):
    return a["ad"] in ("H", "HD")


def is_heteroatom(a):
    return (a["ad"] in AD_COVALENT and a["ad"] not in ("A", "C", "H", "HD")) or a["metal"]


def assign_bonds_ligand(atoms, mobility):
    """model::assign_bonds for a movable ligand, including the bead order Vina iterates in."""
    n = len(atoms)
    X = np.array([a["xyz"] for a in atoms])
    beads = []
    for i in range(n):
        for b in beads:
            if float(np.sum((X[i] - b[0]) ** 2)) < 225.0:
                b[1].append(i)
                break
        else:
            beads.append((X[i].copy(), [i]))
    bonds = [[] for _ in range(n)]  # list of (j, rotatable)
    for i in range(n):
        ci = AD_COVALENT.get(atoms[i]["ad"], MAX_COVALENT)
        bead_cut = (15.0 + 1.1 * (ci + MAX_COVALENT)) ** 2
        relevant = []
        for b in beads:
            if float(np.sum((b[0] - X[i]) ** 2)) > bead_cut:
                continue
            for j in b[1]:
                dt = mobility(i, j)
                if dt != "VARIABLE" and i != j:
                    r2 = d2(X[i], X[j])
                    if r2 < (1.1 * (ci + MAX_COVALENT)) ** 2:
                        relevant.append(j)
        for j in relevant:
            if j <= i:
                continue
            bl = covalent_radius(atoms[i]) + covalent_radius(atoms[j])
            r2 = d2(X[i], X[j])
            if r2 < (1.1 * bl) ** 2 and not atom_exists_between(X, mobility, i, j, relevant, r2):
                rot = mobility(i, j) == "ROTOR"
                bonds[i].append((j, rot))
                bonds[j].append((i, rot))
    return bonds


def d2(a, b):
    dx = a[0] - b[0]
    dy = a[1] - b[1]
    dz = a[2] - b[2]
    return dx * dx + dy * dy + dz * dz


def atom_exists_between(X, mobility, a, b, relevant, r2):
    for c in relevant:
        if c == a or c == b:
            continue
        if mobility(a, c) != "VARIABLE" and mobility(b, c) != "VARIABLE" and \
                d2(X[a], X[c]) < r2 and d2(X[b], X[c]) < r2:
            return True
    return False


def assign_bonds_rigid(atoms):
    """model::assign_bonds for the rigid receptor (every pair is DISTANCE_FIXED). Bond order
    does not matter here (only typing uses receptor bonds), so this is vectorised."""
    X = np.array([a["xyz"] for a in atoms])
    cov = np.array([covalent_radius(a) for a in atoms])
    n = len(atoms)
    # candidate neighbours by a coarse cell list
    cut = 1.1 * (MAX_COVALENT + METAL_COVALENT)
    cells = {}
    keys = np.floor(X / cut).astype(int)
    for i, k in enumerate(map(tuple, keys)):
        cells.setdefault(k, []).append(i)
    bonds = [[] for _ in range(n)]
    for i in range(n):
        ci = AD_COVALENT.get(atoms[i]["ad"], MAX_COVALENT)
        k = keys[i]
        cand = []
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    cand.extend(cells.get((k[0] + dx, k[1] + dy, k[2] + dz), ()))
        cand = np.array(sorted(cand))
        dd = np.array([d2(X[i], X[j]) for j in cand])
        relevant = [int(j) for j, r2 in zip(cand, dd) if j != i and r2 < (1.1 * (ci + MAX_COVALENT)) ** 2]
        for j in relevant:
            if j <= i:
                continue
            r2 = d2(X[i], X[j])
            if r2 < (1.1 * (cov[i] + cov[j])) ** 2:
                between = False
                for c in relevant:
                    if c in (i, j):
                        continue
                    if d2(X[i], X[c]) < r2 and d2(X[j], X[c]) < r2:
                        between = True
                        break
                if not between:
                    bonds[i].append((j, False))
                    bonds[j].append((i, False))
    return bonds


def assign_xs(atoms, bonds):
    """model::assign_types: XS type of every atom (None for hydrogens)."""
    out = []
    for i, a in enumerate(atoms):
        el = AD_ELEMENT.get(a["ad"], "Met" if a["metal"] else None)
        acceptor = a["ad"] in ("OA", "NA")
        donor = el == "Met" or any(atoms[j]["ad"] == "HD" for j, _ in bonds[i])
        hetero = any(is_heteroatom(atoms[j]) for j, _ in bonds[i])
        if el == "H":
            x = None
        elif el == "C":
            x = "C_P" if hetero else "C_H"
        elif el in ("N", "O"):
            x = el + ("_DA" if acceptor and donor else "_A" if acceptor else "_D" if donor else "_P")
        elif el == "S":
            x = "S_P"
        elif el == "P":
            x = "P_P"
        elif el in ("F", "Cl", "Br", "I"):
            x = el + "_H"
        elif el in ("Si", "At"):
            x = el
        elif el == "Met":
            x = "Met_D"
        else:
            raise RuntimeError("cannot type " + a["ad"])
        out.append(x)
    return out


def bonded_to(bonds, a, n, out):
    """model::bonded_to -- Vina's depth-limited DFS (an atom already seen is not re-expanded)."""
    if a not in out:
        out.append(a)
        if n > 0:
            for j, _ in bonds[a]:
                bonded_to(bonds, j, n - 1, out)


def intra_pairs(tree, bonds, xs):
    pairs = []
    n = len(tree.atoms)
    for i in range(n):
        near = []
        bonded_to(bonds, i, 3, near)
        for j in range(i + 1, n):
            if tree.mobility(i, j) == "VARIABLE" and j not in near and \
                    xs[i] is not None and xs[j] is not None:
                pairs.append((i, j))
    return pairs


def num_tors(atoms, bonds):
    """conf_independent_inputs: sum over heavy atoms of 0.5 * (rotatable bonds to heavy atoms
    that themselves have more than one heavy neighbour)."""
    def heavy_deg(k):
        return sum(1 for j, _ in bonds[k] if not is_hydrogen(atoms[j]))
    acc = 0.0
    for i, a in enumerate(atoms):
        if is_hydrogen(a):
            continue
        ar = sum(1 for j, rot in bonds[i] if rot and not is_hydrogen(atoms[j]) and heavy_deg(j) > 1)
        acc += 0.5 * ar
    return acc


# ==============================================================================================
# The scoring function (potentials.h, scoring_function.h, precalculate.h, non_cache.cpp)
# ==============================================================================================
def slope_step(x_bad, x_good, x):
    x = np.asarray(x, float)
    if x_bad < x_good:
        out = np.where(x <= x_bad, 0.0, np.where(x >= x_good, 1.0, (x - x_bad) / (x_good - x_bad)))
    else:
        out = np.where(x >= x_bad, 0.0, np.where(x <= x_good, 1.0, (x - x_bad) / (x_good - x_bad)))
    return out


def term_values(sf, t1, t2, r):
    """Unweighted terms for one XS type pair at distances r (numpy array); 0 at r >= 8."""
    r = np.asarray(r, float)
    inside = r < 8.0
    if sf == "vina":
        R = XS_RADIUS_VINA[t1] + XS_RADIUS_VINA[t2]
        d = r - R
        g1 = np.exp(-(d / 0.5) ** 2)
        g2 = np.exp(-((r - (R + 3.0)) / 2.0) ** 2)
        rep = np.where(d > 0, 0.0, d * d)
        hyd = slope_step(1.5, 0.5, d) if (t1 in HYDROPHOBIC and t2 in HYDROPHOBIC) else 0 * d
        hb = slope_step(0.0, -0.7, d) if ((t1 in DONOR and t2 in ACCEPTOR) or (t2 in DONOR and t1 in ACCEPTOR)) else 0 * d
        terms = [g1, g2, rep, hyd, hb]
    else:
        R = XS_RADIUS_VINARDO[t1] + XS_RADIUS_VINARDO[t2]
        d = r - R
        g = np.exp(-(d / 0.8) ** 2)
        rep = np.where(d > 0, 0.0, d * d)
        hyd = slope_step(2.5, 0.0, d) if (t1 in HYDROPHOBIC and t2 in HYDROPHOBIC) else 0 * d
        hb = slope_step(0.0, -0.6, d) if ((t1 in DONOR and t2 in ACCEPTOR) or (t2 in DONOR and t1 in ACCEPTOR)) else 0 * d
        terms = [g, rep, hyd, hb]
    return [np.where(inside, t, 0.0) for t in terms]


class Table:
    """precalculate(_byatom): for each type pair the weighted energy sampled at r^2 = k/32,
    k = 0 .. n-1 with n = int(32 * 20^2) + 3 = 12803; eval_fast(r2) = fast[int(32 * r2)] with
    fast[k] = (smooth[k] + smooth[k+1]) / 2 (fast[n-1] = smooth[n-1] / 2)."""
    FACTOR = 32.0
    N = int(32.0 * 20.0 * 20.0) + 3

    def __init__(self, sf, weights):
        self.sf = sf
        self.w = np.asarray(weights, float)
        self.rs = np.sqrt(np.arange(self.N) / self.FACTOR)
        self.cache = {}

    def fast(self, t1, t2):
        key = (min(t1, t2), max(t1, t2))
        if key not in self.cache:
            terms = term_values(self.sf, key[0], key[1], self.rs)
            smooth = np.zeros(self.N)
            for w, t in zip(self.w, terms):
                smooth = smooth + w * t
            f = np.empty(self.N)
            f[:-1] = (smooth[:-1] + smooth[1:]) / 2
            f[-1] = smooth[-1] / 2
            self.cache[key] = f
        return self.cache[key]

    def exact(self, t1, t2, r2):
        terms = term_values(self.sf, t1, t2, np.sqrt(r2))
        e = 0 * r2
        for w, t in zip(self.w, terms):
            e = e + w * t
        return e


def curl(e, v=1000.0):
    return np.where(e > 0, e * (v / (v + e)), e)


def reimpl_score(sf, weights, rec_xyz, rec_xs, lig_xyz, lig_xs, pairs, ntors, use_table=True):
    """Vina's score() for a rigid receptor and one ligand: inter = sum over ligand heavy atoms
    of curl(sum over receptor heavy atoms with r^2 < 64 of table(r^2)); intra = sum over the
    ligand's interacting pairs of curl(table(r^2)); total = inter / (1 + w_rot * N_tors)."""
    tab = Table(sf, weights[:-2])
    rec_xs = np.asarray(rec_xs)
    inter = 0.0
    for i in range(len(lig_xyz)):
        diff = lig_xyz[i] - rec_xyz
        r2 = diff[:, 0] * diff[:, 0] + diff[:, 1] * diff[:, 1] + diff[:, 2] * diff[:, 2]
        sel = r2 < 64.0
        e = 0.0
        for t in np.unique(rec_xs[sel]):
            rr = r2[sel & (rec_xs == t)]
            if use_table:
                e += float(np.sum(tab.fast(lig_xs[i], t)[(32.0 * rr).astype(np.int64)]))
            else:
                e += float(np.sum(tab.exact(lig_xs[i], t, rr)))
        inter += float(curl(e))
    intra = 0.0
    for i, j in pairs:
        r2 = d2(lig_xyz[i], lig_xyz[j])
        if r2 < 64.0:
            if use_table:
                e = tab.fast(lig_xs[i], lig_xs[j])[int(32.0 * r2)]
            else:
                e = float(tab.exact(lig_xs[i], lig_xs[j], np.array([r2]))[0])
            intra += float(curl(e))
    w_rot = weights[-1]
    total = inter / (1.0 + w_rot * ntors)
    return dict(inter=inter, intra=intra, total=total)


# ==============================================================================================
# Vina runs
# ==============================================================================================
def vina_session(sf, weights, rec_pdbqt, lig_text, center, size, spacing):
    from vina import Vina
    v = Vina(sf_name=sf, seed=1, verbosity=0, cpu=1)
    v.set_weights(list(weights))
    v.set_receptor(rec_pdbqt)
    v.set_ligand_from_string(lig_text)
    v.compute_vina_maps(center=list(center), box_size=list(size), spacing=spacing)
    return v


def score_all(sf, weights, rec_pdbqt, pose_texts, center, size):
    v = vina_session(sf, weights, rec_pdbqt, pose_texts[0], center, size, SCORE_SPACING)
    out = []
    for t in pose_texts:
        v.set_ligand_from_string(t)
        out.append(list(v._vina.score()))  # the unrounded doubles (Vina.score() rounds to 3 d.p.)
    return out


def pose_pdbqt(tree_text, serial_to_xyz):
    out = []
    for l in tree_text.splitlines():
        if l.startswith("ATOM  ") or l.startswith("HETATM"):
            x, y, z = serial_to_xyz[int(l[6:11])]
            l = l[:30] + fmt8(x) + fmt8(y) + fmt8(z) + l[54:]
        out.append(l)
    return "\n".join(out) + "\n"


def read_pose_pdbqt(text):
    xyz = {}
    for l in text.splitlines():
        if l.startswith("ATOM  ") or l.startswith("HETATM"):
            xyz[int(l[6:11])] = (float(l[30:38]), float(l[38:46]), float(l[46:54]))
    return xyz


# ==============================================================================================
# Main
# ==============================================================================================
OB_RECEPTOR_PREP = ("Open Babel python API: OBConversion.ReadFile(pdb); mol.AddHydrogens(False, False) "
                    "(what obabel -h does); OBChargeModel.FindType('gasteiger').ComputeCharges(mol); "
                    "write pdbqt with write option 'r' (rigid). NOTE: the one-line CLI "
                    "'obabel rec.pdb -xr -h --partialcharge gasteiger' runs the charge op BEFORE adding "
                    "hydrogens (transform.cpp: OBOp::DoOps precedes AddHydrogens), and without "
                    "--partialcharge every charge is written as 0.000")
OB_LIGAND_PREP = ("Open Babel python API: OBConversion.ReadFile(sdf, all hydrogens present); "
                  "OBChargeModel.FindType('gasteiger').ComputeCharges(mol); write pdbqt (default: "
                  "torsion tree, non-polar hydrogens merged) -- equivalent to "
                  "'obabel lig.sdf --partialcharge gasteiger -O lig.pdbqt'")


def ob_to_pdbqt(in_path, in_fmt, out_path, add_h, rigid):
    from openbabel import openbabel as ob
    ob.obErrorLog.SetOutputLevel(0)
    conv = ob.OBConversion()
    conv.SetInAndOutFormats(in_fmt, "pdbqt")
    mol = ob.OBMol()
    if not conv.ReadFile(mol, in_path):
        raise RuntimeError("Open Babel could not read " + in_path)
    if add_h:
        mol.AddHydrogens(False, False)
    ok = bool(ob.OBChargeModel.FindType("gasteiger").ComputeCharges(mol))
    if rigid:
        conv.AddOption("r", ob.OBConversion.OUTOPTIONS)
    if not conv.WriteFile(mol, out_path):
        raise RuntimeError("Open Babel could not write " + out_path)
    conv.CloseOutFile()
    return ok


def prepare_complex(cx, pdb_dir, work):
    from rdkit import Chem
    rec_src = os.path.join(pdb_dir, cx["receptor"])
    st = load_structure(rec_src)
    rec_pdb = os.path.join(work, cx["id"] + "_rec.pdb")
    n_rec_in = write_receptor_pdb(st, rec_pdb)
    rec_pdbqt = os.path.join(work, cx["id"] + "_rec.pdbqt")
    rec_ok = ob_to_pdbqt(rec_pdb, "pdb", rec_pdbqt, add_h=True, rigid=True)

    info = {"receptor_source": cx["receptor"],
            "receptor_selection": "first model; first alternate conformer (gemmi "
                                  "remove_alternative_conformations); polymer ATOM records only "
                                  "(every HETATM record -- water, ions, cofactors, ligand -- removed)",
            "receptor_atoms_selected": n_rec_in,
            "receptor_prep": OB_RECEPTOR_PREP,
            "receptor_gasteiger_ok": rec_ok}
    if cx.get("sdf"):
        mol, heavy_idx, orig = ligand_from_sdf(os.path.join(pdb_dir, cx["sdf"]))
        info["ligand_source"] = cx["sdf"]
        info["ligand_input_atoms"] = [{"sdf_index": i} for i in heavy_idx]
        if cx.get("ligand"):
            res = ligand_residue(st, *cx["ligand"])
            pdb_heavy = [(a.name, a.serial, (a.pos.x, a.pos.y, a.pos.z)) for a in res
                         if a.element.name not in ("H", "D")]
            info["ligand_also_in"] = "%s residue %s chain %s" % (cx["receptor"], *cx["ligand"])
            # name each SDF heavy atom after the PDB atom at the same place (if any)
            for rec, p in zip(info["ligand_input_atoms"], orig):
                best = min(pdb_heavy, key=lambda t: d2(t[2], p))
                if d2(best[2], p) < 1e-4:
                    rec["pdb_name"] = best[0]
                    rec["pdb_serial"] = best[1]
    else:
        res = ligand_residue(st, *cx["ligand"])
        mol, names, serials, orig = ligand_from_pdb_residue(res, cx["template"])
        info["ligand_source"] = "%s residue %s chain %s (HETATM, heavy atoms)" % (cx["receptor"], *cx["ligand"])
        info["ligand_bond_order_template"] = cx["template"]
        info["ligand_input_atoms"] = [{"pdb_name": n, "pdb_serial": s} for n, s in zip(names, serials)]
        heavy_idx = list(range(len(names)))
    mol, n_added = add_h_with_coords(mol)
    info["ligand_hydrogens_added_by_rdkit"] = n_added
    info["ligand_smiles"] = Chem.MolToSmiles(Chem.RemoveHs(mol))
    lig_sdf = os.path.join(work, cx["id"] + "_lig.sdf")
    Chem.MolToMolFile(mol, lig_sdf)
    lig_pdbqt = os.path.join(work, cx["id"] + "_lig.pdbqt")
    info["ligand_gasteiger_ok"] = ob_to_pdbqt(lig_sdf, "sdf", lig_pdbqt, add_h=False, rigid=False)
    info["ligand_prep"] = OB_LIGAND_PREP
    conf = mol.GetConformer()
    sdf_xyz = np.array([tuple(conf.GetAtomPosition(i)) for i in range(mol.GetNumAtoms())])
    sdf_heavy = [i for i in range(mol.GetNumAtoms()) if mol.GetAtomWithIdx(i).GetAtomicNum() > 1]
    return info, rec_pdbqt, lig_pdbqt, mol, sdf_xyz, heavy_idx, np.array(orig), sdf_heavy


def meeko_types(mol):
    """Ligand PDBQT atom types meeko would write (for the OB/meeko comparison only)."""
    try:
        from meeko import MoleculePreparation, PDBQTWriterLegacy
        prep = MoleculePreparation()
        setups = prep.prepare(mol)
        s, ok, err = PDBQTWriterLegacy.write_string(setups[0])
        if not ok:
            return None, err
        return s, None
    except Exception as e:  # pragma: no cover - informative only
        return None, repr(e)


def run(args):
    import vina
    from openbabel import openbabel as ob
    import rdkit
    import gemmi
    work = tempfile.mkdtemp(prefix="vina_ref_")
    result = {
        "about": ("Reference values from AutoDock Vina 1.2 (python bindings) for bump's Vina/Vinardo "
                  "scoring. Generated by tests/reference/vina/make_reference.py; the formulas are "
                  "in docs/vina-scoring.md."),
        "versions": {
            "python": platform.python_version(),
            "vina": vina.__version__ if hasattr(vina, "__version__") else "?",
            "openbabel_wheel": _dist_version("openbabel-wheel"),
            "openbabel_release": ob.OBReleaseVersion(),
            "rdkit": rdkit.__version__,
            "gemmi": gemmi.__version__,
            "numpy": np.__version__,
            "meeko": _dist_version("meeko"),
        },
        "conventions": {
            "score_columns": SCORE_COLUMNS,
            "score_columns_note": ("Vina._vina.score() (unrounded) returns [total, lig_inter, flex_inter, "
                                   "other_inter, flex_intra, lig_intra, torsions, lig_intra_best_pose]; "
                                   "with a rigid receptor total = lig_inter / (1 + w_rot * N_tors) and "
                                   "torsions = total - lig_inter (the intra energy is added and subtracted)."),
            "vina_weights": dict(zip(VINA_TERMS + ["glue", "rot"], VINA_WEIGHTS)),
            "vinardo_weights": dict(zip(VINARDO_TERMS + ["glue", "rot"], VINARDO_WEIGHTS)),
            "set_weights_layout_vina": VINA_TERMS + ["glue", "rot"],
            "set_weights_layout_vinardo": VINARDO_TERMS + ["glue", "rot"],
            "terms_weighted": ("score with set_weights = default weight for that term, 0 for the other "
                               "terms and for rot (so no torsion divisor): {inter: lig_inter, intra: lig_intra}"),
            "terms_raw": ("unweighted term sum = -(score with that term's weight = -1, others 0, rot 0). "
                          "Using -1 keeps every per-atom sum <= 0 so Vina's curl (e -> e*1000/(1000+e) for "
                          "e > 0) never acts; weight +1 would be distorted by it."),
            "transform": ("x' = c + R (x - c) + t, c = centroid of the ligand's heavy atoms as read from the "
                          "input file, R = rotation by angle_deg about unit(axis) (right-handed, Rodrigues), "
                          "t = shift. Applied to every ligand atom (hydrogens too)."),
            "coordinates_as_scored": ("the ligand heavy-atom coordinates written into the PDBQT Vina "
                                      "scored (8-character fields, as many decimals as fit); equal to the "
                                      "transformed input coordinates to within 5e-5 A"),
            "receptor_atoms": ("receptor heavy atoms within %.1f A of any ligand heavy atom of any scored pose "
                               "of the complex" % RECEPTOR_SHELL),
            "atom_fields_receptor": ["chain", "resname", "resnum", "name", "x", "y", "z", "ad", "xs",
                                     "q", "n_hd_bonded", "bonded_to_heteroatom"],
            "atom_fields_ligand": ["name", "x", "y", "z", "ad", "xs", "q", "pdbqt_serial",
                                   "input_heavy_index", "n_hd_bonded", "bonded_to_heteroatom", "node"],
        },
        "complexes": {},
    }
    for cx in COMPLEXES:
        print("==", cx["id"], flush=True)
        try:
            entry = do_complex(cx, args.pdb_dir, work)
        except Exception as e:
            import traceback
            traceback.print_exc()
            entry = {"status": "failed: %s" % (str(e).splitlines()[0] if str(e) else repr(e))}
        result["complexes"][cx["id"]] = entry
    if args.keep:
        print("kept work directory", work)
    else:
        shutil.rmtree(work, ignore_errors=True)
    text = dumps(result)
    with open(args.out, "w") as f:
        f.write(text)
    print("wrote", args.out, len(text), "bytes")


def _dist_version(name):
    try:
        from importlib.metadata import version
        return version(name)
    except Exception:
        return None


def do_complex(cx, pdb_dir, work):
    info, rec_pdbqt, lig_pdbqt, mol, sdf_xyz, heavy_idx, orig_heavy, sdf_heavy = \
        prepare_complex(cx, pdb_dir, work)
    lig_text = open(lig_pdbqt).read()
    rec_text = open(rec_pdbqt).read()
    tree = LigandTree(lig_text)
    latoms = tree.atoms
    # map every PDBQT atom to the prepared SDF atom at the same place (PDBQT has 3 decimals)
    exact = {}
    pdbqt_to_sdf = {}
    for a in latoms:
        dd = np.sum((sdf_xyz - np.array(a["xyz"])) ** 2, axis=1)
        k = int(np.argmin(dd))
        if dd[k] > (0.0011 ** 2) * 3:
            raise RuntimeError("PDBQT atom %d not found in the prepared SDF" % a["serial"])
        pdbqt_to_sdf[a["serial"]] = k
        exact[a["serial"]] = tuple(float(v) for v in sdf_xyz[k])
    # heavy atoms in the input's order -> Vina order
    heavy_vina = [i for i, a in enumerate(latoms) if not is_hydrogen(a)]
    sdf_to_input_heavy = {s: n for n, s in enumerate(sdf_heavy)}
    centroid = orig_heavy.mean(axis=0)

    # ---- poses -------------------------------------------------------------------------------
    seed = zlib.crc32(cx["id"].encode())
    rng = np.random.default_rng(seed)
    poses = [dict(id="crystal", kind="crystal", axis=[0.0, 0.0, 1.0], angle_deg=0.0, shift=[0.0, 0.0, 0.0])]

    def rand_unit():
        v = rng.normal(size=3)
        return v / np.linalg.norm(v)
    for k in range(N_SMALL):
        axis = np.round(rand_unit(), 6)
        ang = round(float(rng.uniform(0.0, SMALL_MAX_ANGLE)), 6)
        sh_ = np.round(rand_unit() * rng.uniform(0.0, SMALL_MAX_SHIFT), 6)
        poses.append(dict(id="small_%d" % (k + 1), kind="small", axis=axis.tolist(), angle_deg=ang, shift=sh_.tolist()))
    for k, (s, a) in enumerate(LARGE):
        axis = np.round(rand_unit(), 6)
        sh_ = np.round(rand_unit() * s, 6)
        poses.append(dict(id="large_%d" % (k + 1), kind="large", axis=axis.tolist(), angle_deg=a, shift=sh_.tolist()))
    serial_list = [a["serial"] for a in latoms]
    base = np.array([exact[s] for s in serial_list])
    for p in poses:
        moved = apply_transform(base, centroid, p["axis"], p["angle_deg"], p["shift"]) if p["kind"] != "crystal" else base
        p["_map"] = {s: tuple(m) for s, m in zip(serial_list, moved)}
        p["_text"] = pose_pdbqt(lig_text, p["_map"])
        seen = read_pose_pdbqt(p["_text"])
        p["_xyz_vina"] = np.array([seen[a["serial"]] for a in latoms])

    # ---- box -----------------------------------------------------------------------------------
    allh = np.vstack([p["_xyz_vina"][heavy_vina] for p in poses])
    center = np.round(centroid, 3)
    half = np.max(np.abs(allh - center), axis=0) + BOX_MARGIN
    size = np.ceil(2 * half)
    box = dict(center=center.tolist(), size=size.tolist(), spacing_score=SCORE_SPACING,
               spacing_optimize=OPT_SPACING)

    # ---- Vina model reconstruction (types, bonds, pairs) ---------------------------------------
    ratoms = parse_receptor_pdbqt(rec_text)
    rbonds = assign_bonds_rigid(ratoms)
    rxs = assign_xs(ratoms, rbonds)
    lbonds = assign_bonds_ligand(latoms, tree.mobility)
    lxs = assign_xs(latoms, lbonds)
    pairs = intra_pairs(tree, lbonds, lxs)
    ntors = num_tors(latoms, lbonds)

    rec_heavy = [i for i, a in enumerate(ratoms) if rxs[i] is not None]
    RX = np.array([ratoms[i]["xyz"] for i in rec_heavy])
    RXS = [rxs[i] for i in rec_heavy]

    # ---- Vina scoring --------------------------------------------------------------------------
    texts = [p["_text"] for p in poses]
    results = {}
    configs = {"vina": [("full", VINA_WEIGHTS)], "vinardo": [("full", VINARDO_WEIGHTS)]}
    for sf, terms, wdef in (("vina", VINA_TERMS, VINA_WEIGHTS), ("vinardo", VINARDO_TERMS, VINARDO_WEIGHTS)):
        for ti, t in enumerate(terms):
            w = [0.0] * (len(terms) + 2)
            w[ti] = wdef[ti]
            configs[sf].append(("weighted:" + t, tuple(w)))
            w = [0.0] * (len(terms) + 2)
            w[ti] = -1.0
            configs[sf].append(("raw:" + t, tuple(w)))
    for sf in ("vina", "vinardo"):
        for name, w in configs[sf]:
            results[(sf, name)] = score_all(sf, w, rec_pdbqt, texts, box["center"], box["size"])

    # ---- independent re-computation ------------------------------------------------------------
    worst = {"vina": 0.0, "vinardo": 0.0}
    pose_out = []
    lig_heavy_xs = [lxs[i] for i in heavy_vina]
    vina_to_heavy = {v: n for n, v in enumerate(heavy_vina)}
    hpairs = [(vina_to_heavy[i], vina_to_heavy[j]) for i, j in pairs]
    for pi, p in enumerate(poses):
        LX = p["_xyz_vina"][heavy_vina]
        entry = {"id": p["id"], "kind": p["kind"],
                 "transform": {"axis": p["axis"], "angle_deg": p["angle_deg"], "shift": p["shift"],
                               "centroid": centroid.tolist()},
                 "ligand_heavy_xyz_as_scored": LX.tolist()}
        for sf, terms, wdef in (("vina", VINA_TERMS, VINA_WEIGHTS), ("vinardo", VINARDO_TERMS, VINARDO_WEIGHTS)):
            full = results[(sf, "full")][pi]
            d = {"score": dict(zip(SCORE_COLUMNS, full))}
            d["divisor"] = full[1] / full[0] if abs(full[0]) > 1e-12 else None
            tw, tr = {}, {}
            for t in terms:
                s = results[(sf, "weighted:" + t)][pi]
                tw[t] = {"inter": s[1], "intra": s[5]}
                s = results[(sf, "raw:" + t)][pi]
                tr[t] = {"inter": -s[1], "intra": -s[5]}
            d["terms_weighted"] = tw
            d["terms_raw"] = tr
            # re-computation
            mine = reimpl_score(sf, wdef, RX, RXS, LX, lig_heavy_xs, hpairs, ntors)
            exact_fn = reimpl_score(sf, wdef, RX, RXS, LX, lig_heavy_xs, hpairs, ntors, use_table=False)
            d["spec_check"] = {"inter": mine["inter"], "intra": mine["intra"], "total": mine["total"],
                               "inter_without_table": exact_fn["inter"],
                               "intra_without_table": exact_fn["intra"],
                               "total_without_table": exact_fn["total"]}
            diffs = [abs(mine["inter"] - full[1]), abs(mine["intra"] - full[5]), abs(mine["total"] - full[0])]
            for ti, t in enumerate(terms):
                w = [0.0] * (len(terms) + 2)
                w[ti] = -1.0
                m = reimpl_score(sf, w, RX, RXS, LX, lig_heavy_xs, hpairs, 0.0)
                diffs += [abs(-m["inter"] - tr[t]["inter"]), abs(-m["intra"] - tr[t]["intra"])]
                w[ti] = wdef[ti]
                m = reimpl_score(sf, w, RX, RXS, LX, lig_heavy_xs, hpairs, 0.0)
                diffs += [abs(m["inter"] - tw[t]["inter"]), abs(m["intra"] - tw[t]["intra"])]
            worst[sf] = max(worst[sf], max(diffs))
            entry[sf] = d
        pose_out.append(entry)

    # ---- optimisation --------------------------------------------------------------------------
    opt_out = []
    cryst = poses[0]["_xyz_vina"][heavy_vina]
    for pid in OPTIMIZE_POSES:
        p = next(q for q in poses if q["id"] == pid)
        for sf, w in (("vina", VINA_WEIGHTS),):
            v = vina_session(sf, w, rec_pdbqt, p["_text"], box["center"], box["size"], OPT_SPACING)
            before = list(v._vina.score())
            after = list(v._vina.optimize(0))
            outp = os.path.join(work, "%s_%s_opt.pdbqt" % (cx["id"], pid))
            v.write_pose(outp, overwrite=True)
            got = read_pose_pdbqt(open(outp).read())
            # write_pose renumbers nothing: serials follow the input PDBQT
            X = np.array([got[latoms[i]["serial"]] for i in heavy_vina])
            rmsd = float(np.sqrt(np.mean(np.sum((X - cryst) ** 2, axis=1))))
            rmsd0 = float(np.sqrt(np.mean(np.sum((p["_xyz_vina"][heavy_vina] - cryst) ** 2, axis=1))))
            n_mov = len(latoms)
            opt_out.append({"pose": pid, "sf": sf, "max_steps": (25 + n_mov) // 3,
                            "before": dict(zip(SCORE_COLUMNS, before)),
                            "after": dict(zip(SCORE_COLUMNS, after)),
                            "rmsd_to_crystal_before": rmsd0, "rmsd_to_crystal_after": rmsd,
                            "final_heavy_xyz": X.tolist()})

    # ---- atom records --------------------------------------------------------------------------
    allposes = np.vstack([p["_xyz_vina"][heavy_vina] for p in poses])
    near = []
    for n, i in enumerate(rec_heavy):
        dd = np.min(np.sum((allposes - RX[n]) ** 2, axis=1))
        if dd < RECEPTOR_SHELL ** 2:
            a = ratoms[i]
            near.append([a["chain"], a["resname"], a["resnum"] + a["icode"], a["name"],
                         a["xyz"][0], a["xyz"][1], a["xyz"][2], a["ad_text"], rxs[i], a["q"],
                         sum(1 for j, _ in rbonds[i] if ratoms[j]["ad"] == "HD"),
                         any(is_heteroatom(ratoms[j]) for j, _ in rbonds[i])])
    node_of = {}
    for ni, (b, e, *_r) in enumerate(tree.nodes):
        for k in range(b, e):
            node_of[k] = ni
    lig_rec = []
    for i in heavy_vina:
        a = latoms[i]
        sdf_k = pdbqt_to_sdf[a["serial"]]
        inp = sdf_to_input_heavy.get(sdf_k)
        ex = exact[a["serial"]]
        lig_rec.append([a["name"], ex[0], ex[1], ex[2], a["ad_text"], lxs[i], a["q"], a["serial"],
                        heavy_idx[inp] if inp is not None else None,
                        sum(1 for j, _ in lbonds[i] if latoms[j]["ad"] == "HD"),
                        any(is_heteroatom(latoms[j]) for j, _ in lbonds[i]), node_of.get(i)])
    rot_bonds = sorted({(min(i, j), max(i, j)) for i in range(len(latoms)) for j, r in lbonds[i] if r})

    def heavy_deg(k):
        return sum(1 for j, _ in lbonds[k] if not is_hydrogen(latoms[j]))
    torsions = []
    for i, j in rot_bonds:
        contrib = 0.0
        for x, y in ((i, j), (j, i)):
            if not is_hydrogen(latoms[x]) and not is_hydrogen(latoms[y]) and heavy_deg(y) > 1:
                contrib += 0.5
        torsions.append({"heavy_index": [vina_to_heavy.get(i), vina_to_heavy.get(j)],
                         "pdbqt_serials": [latoms[i]["serial"], latoms[j]["serial"]],
                         "names": [latoms[i]["name"], latoms[j]["name"]],
                         "heavy_degree": [heavy_deg(i), heavy_deg(j)],
                         "num_tors_contribution": contrib})
    n_branches = len(tree.nodes) - 1

    mk_text, mk_err = meeko_types(mol)
    mk_cmp = None
    if mk_text:
        mk_atoms = [parse_atom_line(l) for l in mk_text.splitlines() if l.startswith(("ATOM", "HETATM"))]
        diffs = []
        for a in latoms:
            best = min(mk_atoms, key=lambda b: d2(b["xyz"], a["xyz"]))
            if d2(best["xyz"], a["xyz"]) < 1e-4 and best["ad_text"] != a["ad_text"]:
                diffs.append([a["name"], a["ad_text"], best["ad_text"]])
        tors_mk = sum(1 for l in mk_text.splitlines() if l.startswith("BRANCH"))
        mk_cmp = {"type_differences_openbabel_vs_meeko": diffs, "meeko_branches": tors_mk,
                  "meeko_atoms": len(mk_atoms), "openbabel_atoms": len(latoms),
                  "meeko_hydrogens_written": sum(1 for b in mk_atoms if b["ad_text"] in ("H", "HD"))}
        try:
            v = vina_session("vina", VINA_WEIGHTS, rec_pdbqt, mk_text, box["center"], box["size"], SCORE_SPACING)
            sc = list(v._vina.score())
            mk_cmp["vina_crystal_score_with_meeko_pdbqt"] = dict(zip(SCORE_COLUMNS, sc))
            mk_cmp["vina_num_tors_with_meeko_pdbqt"] = (sc[1] / sc[0] - 1.0) / VINA_WEIGHTS[-1]
        except Exception as e:  # informative only
            mk_cmp["vina_error"] = repr(e)
    elif mk_err:
        mk_cmp = {"error": mk_err}

    return {
        "status": "ok",
        "prep": info,
        "ligand": {
            "pdbqt": lig_text.splitlines(),
            "torsdof": tree.torsdof,
            "n_branches": n_branches,
            "vina_num_tors": ntors,
            "rotatable_bonds": torsions,
            "n_atoms_pdbqt": len(latoms),
            "heavy_atoms": lig_rec,
            "intra_pairs": [list(p) for p in hpairs],
            "heavy_centroid": centroid.tolist(),
            "root_origin_xyz": list(exact[latoms[0]["serial"]]),
        },
        "receptor": {"n_atoms_pdbqt": len(ratoms), "n_heavy": len(rec_heavy),
                     "ad_type_counts": _counts(a["ad_text"] for a in ratoms),
                     "xs_type_counts": _counts(x for x in rxs if x is not None),
                     "atoms_near": near},
        "box": box,
        "poses": pose_out,
        "optimize": opt_out,
        "spec_check_max_abs_diff": {k: "%.3e" % v for k, v in worst.items()},
        "meeko_comparison": mk_cmp,
    }


def _counts(it):
    d = {}
    for x in it:
        d[x] = d.get(x, 0) + 1
    return d


# ==============================================================================================
# Deterministic JSON: sorted keys, floats with 6 decimals, short lists on one line
# ==============================================================================================
def _scalar(x):
    if isinstance(x, bool) or x is None:
        return json.dumps(x)
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        x = float(x)
        if not math.isfinite(x):
            return json.dumps(str(x))
        s = "%.6f" % x
        return "0.000000" if s == "-0.000000" else s
    return json.dumps(x)


def _is_flat(v):
    return isinstance(v, (list, tuple)) and all(not isinstance(e, (list, tuple, dict)) for e in v)


def dumps(obj, indent=0):
    pad = " " * indent
    if isinstance(obj, dict):
        if not obj:
            return "{}"
        items = ["%s %s: %s" % (pad, json.dumps(str(k)), dumps(obj[k], indent + 1)) for k in sorted(obj, key=str)]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(obj, (list, tuple)):
        if _is_flat(obj):
            return "[" + ",".join(_scalar(e) for e in obj) + "]"
        items = [pad + " " + dumps(e, indent + 1) for e in obj]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    return _scalar(obj)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pdb-dir", default="../shared/pdb",
                    help="shared structure folder (default ../shared/pdb, relative to the repo root)")
    ap.add_argument("--out", default="tests/reference/vina/values.json")
    ap.add_argument("--only", help="comma-separated complex ids (for development)")
    ap.add_argument("--keep", action="store_true", help="keep the temporary work directory")
    args = ap.parse_args()
    if args.only:
        keep = set(args.only.split(","))
        COMPLEXES[:] = [c for c in COMPLEXES if c["id"] in keep]
    run(args)


if __name__ == "__main__":
    main()
