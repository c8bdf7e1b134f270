#!/usr/bin/env python3
"""Makes the bond-order perception reference: drug-like molecules written as heavy atoms only,
without bonds (as a PDB HETATM residue gives them), and the Vina types of their N and O atoms as
Open Babel assigns them from the true bond orders.

    python tests/reference/perception/make_perception.py

For each SMILES below: RDKit adds hydrogens, embeds (seed 7) and MMFF-optimises; the heavy atoms
go to tests/data/perception/NAME.pdb (no CONECT, no hydrogens, atom names element + index, a
formal charge in columns 79-80 as a PDB writer puts it, 1- or 1+);
the molecule with its hydrogens and bond orders goes to Open Babel's PDBQT writer, and each N and
O gets the X-Score type Vina reads from that PDBQT (NA/OA accept; an HD bonded makes a donor).
Writes tests/reference/perception/values.json. tests/chemistry.rs checks that bump, reading only
the coordinates, types every N and O the same. Requirements: rdkit, openbabel-wheel, numpy
(tests/reference/vina/requirements.txt).
"""
import json
import os

import numpy as np
from openbabel import openbabel as ob
from openbabel import pybel
from rdkit import Chem, rdBase
from rdkit.Chem import AllChem

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "data", "perception")

MOLECULES = [
    ("uracil5FU", "O=C1NC=C(F)C(=O)N1"),
    ("thymine", "CC1=CNC(=O)NC1=O"),
    ("cytosine_nuc", "NC1=NC(=O)N(C)C=C1"),
    ("guanine9Me", "Cn1cnc2c1nc(N)[nH]c2=O"),
    ("acyclovir", "Nc1nc2n(COCCO)cnc2c(=O)[nH]1"),
    ("caffeine", "Cn1cnc2c1c(=O)n(C)c(=O)n2C"),
    ("theophylline", "Cn1c2nc[nH]c2c(=O)n(C)c1=O"),
    ("phenobarbital", "CCC1(c2ccccc2)C(=O)NC(=O)NC1=O"),
    ("phenytoin", "O=C1NC(=O)C(c2ccccc2)(c2ccccc2)N1"),
    ("2pyridone", "O=c1cccc[nH]1"),
    ("4quinazolinone", "O=c1[nH]cnc2ccccc12"),
    ("oxindole", "O=C1Cc2ccccc2N1"),
    ("isatin", "O=C1Nc2ccccc2C1=O"),
    ("thalidomide", "O=C1CCC(N2C(=O)c3ccccc3C2=O)C(=O)N1"),
    ("allopurinol", "O=c1[nH]cnc2[nH]ncc12"),
    ("olaparib_core", "O=C1NN=Cc2ccccc21"),
    ("pirfenidone", "Cc1ccc(=O)n(-c2ccccc2)c1"),
    ("lumazine", "O=c1[nH]c(=O)c2nccnc2[nH]1"),
    ("folate_pterin", "Nc1nc2ncc(C)nc2c(=O)[nH]1"),
    ("trimethoprim", "COc1cc(Cc2cnc(N)nc2N)cc(OC)c1OC"),
    ("imatinib", "Cc1ccc(NC(=O)c2ccc(CN3CCN(C)CC3)cc2)cc1Nc1nccc(-c2cccnc2)n1"),
    ("benzamidine", "NC(=N)c1ccccc1"),
    ("nicotinamide", "NC(=O)c1cccnc1"),
    ("adenine9Me", "Cn1cnc2c(N)ncnc21"),
    ("quinolone_cipro", "OC(=O)c1cn(C2CC2)c2cc(N3CCNCC3)c(F)cc2c1=O"),
    ("coumarin", "O=c1ccc2ccccc2o1"),
    ("piracetam", "NC(=O)CN1CCCC1=O"),
    ("penicillinG", "CC1(C)SC2C(NC(=O)Cc3ccccc3)C(=O)N2C1C(=O)O"),
    ("hydroxypyridine_mimic_4pyrimidinone", "O=c1ccnc[nH]1"),
    ("sildenafil_core", "CCCc1nn(C)c2c1nc([nH]c2=O)-c1ccccc1OCC"),
    ("riboflavin_core", "Cc1cc2nc3c(=O)[nH]c(=O)nc-3n(C)c2cc1C"),
    ("aspirin", "CC(=O)Oc1ccccc1C(=O)O"),
    ("paracetamol", "CC(=O)Nc1ccc(O)cc1"),
    ("sulfamethoxazole", "Cc1cc(NS(=O)(=O)c2ccc(N)cc2)no1"),
    ("celecoxib", "Cc1ccc(-c2cc(C(F)(F)F)nn2-c2ccc(S(N)(=O)=O)cc2)cc1"),
    ("diazepam", "CN1C(=O)CN=C(c2ccccc2)c2cc(Cl)ccc21"),
    ("warfarin", "CC(=O)CC(c1ccccc1)c1c(O)c2ccccc2oc1=O"),
    ("nifedipine", "COC(=O)C1=C(C)NC(C)=C(C(=O)OC)C1c1ccccc1[N+](=O)[O-]"),
    ("metformin", "CN(C)C(=N)NC(=N)N"),
    ("histamine", "NCCc1c[nH]cn1"),
    ("melatonin", "COc1ccc2[nH]cc(CCNC(C)=O)c2c1"),
    ("nicotine", "CN1CCCC1c1cccnc1"),
    ("omeprazole", "COc1ccc2[nH]c(S(=O)Cc3ncc(C)c(OC)c3C)nc2c1"),
    ("furosemide", "NS(=O)(=O)c1cc(C(=O)O)c(NCc2ccco2)cc1Cl"),
    ("losartan_tetrazole", "CCCCc1nc(Cl)c(CO)n1Cc1ccc(-c2ccccc2-c2nn[nH]n2)cc1"),
    ("oseltamivir", "CCOC(=O)C1=CC(OC(CC)CC)C(NC(C)=O)C(N)C1"),
    ("methotrexate", "CN(Cc1cnc2nc(N)nc(N)c2n1)c1ccc(C(=O)NC(CCC(=O)O)C(=O)O)cc1"),
    ("gefitinib", "COc1cc2ncnc(Nc3ccc(F)c(Cl)c3)c2cc1OCCCN1CCOCC1"),
    ("ketoconazole_core", "CC(=O)N1CCN(c2ccc(OC)cc2)CC1"),
    ("indomethacin", "COc1ccc2c(c1)c(CC(=O)O)c(C)n2C(=O)c1ccc(Cl)cc1"),
    ("uridine", "O=c1ccn(C2OC(CO)C(O)C2O)c(=O)[nH]1"),
    ("cytidine", "Nc1ccn(C2OC(CO)C(O)C2O)c(=O)n1"),
    ("guanosine", "Nc1nc2c(ncn2C2OC(CO)C(O)C2O)c(=O)[nH]1"),
    ("xanthine", "O=c1[nH]c(=O)c2[nH]cnc2[nH]1"),
    ("barbital", "CCC1(CC)C(=O)NC(=O)NC1=O"),
    ("hydrochlorothiazide", "NS(=O)(=O)c1cc2c(cc1Cl)NCNS2(=O)=O"),
    ("tolbutamide", "CCCCNC(=O)NS(=O)(=O)c1ccc(C)cc1"),
    ("captopril", "CC(CS)C(=O)N1CCCC1C(=O)O"),
    ("levetiracetam", "CCC(C(N)=O)N1CCCC1=O"),
    ("quinine_core", "COc1ccc2nccc(C(O)C3CC4CCN3CC4C=C)c2c1"),
    ("fluconazole", "OC(Cn1cncn1)(Cn1cncn1)c1ccc(F)cc1F"),
    ("metronidazole", "Cc1ncc([N+](=O)[O-])n1CCO"),
    ("allantoin_like_hydantoin", "NC(=O)NC1NC(=O)NC1=O"),
    ("zidovudine", "Cc1cn(C2CC(N=[N+]=[N-])C(CO)O2)c(=O)[nH]c1=O"),
    ("mercaptopurine_oxo", "O=c1[nH]cnc2nc[nH]c12"),
    ("ondansetron", "Cc1nccn1CC1CCc2c(c3ccccc3n2C)C1=O"),
    ("lamotrigine", "Nc1nnc(-c2cccc(Cl)c2Cl)c(N)n1"),
    ("praziquantel", "O=C(C1CCCCC1)N1CC(=O)N2CCc3ccccc3C2C1"),
    ("sitagliptin_core", "NC(CC(=O)N1CCn2c(nnc2C(F)(F)F)C1)Cc1cc(F)c(F)cc1F"),
    ("isoniazid", "NNC(=O)c1ccncc1"),
    ("chloramphenicol", "OCC(NC(=O)C(Cl)Cl)C(O)c1ccc([N+](=O)[O-])cc1"),
    ("pyrazinamide", "NC(=O)c1cnccn1"),
    ("indazole", "c1ccc2[nH]ncc2c1"),
    ("indazole_3_carboxamide", "NC(=O)c1n[nH]c2ccccc12"),
    ("benzimidazole", "c1ccc2[nH]cnc2c1"),
    ("azaindole7", "c1cnc2[nH]ccc2c1"),
    ("carbazole", "c1ccc2c(c1)[nH]c1ccccc12"),
    ("purine", "c1ncc2[nH]cnc2n1"),
    ("benzoate", "[O-]C(=O)c1ccccc1"),
    ("butylammonium", "CCCC[NH3+]"),
    ("glycine_zwitterion", "[NH3+]CC(=O)[O-]"),
    ("phenylphosphonate", "O=P([O-])([O-])c1ccccc1"),
    ("primidone", "CCC1(c2ccccc2)C(=O)NCNC1=O"),
    ("cimetidine", "CN=C(NC#N)NCCSCc1nc[nH]c1C"),
    ("tinidazole_like", "CCS(=O)(=O)CCn1c(C)ncc1[N+](=O)[O-]"),
    ("ribavirin", "NC(=O)c1ncn(C2OC(CO)C(O)C2O)n1"),
    ("favipiravir", "NC(=O)c1nc(F)c[nH]c1=O"),
    ("minoxidil_like", "Nc1cc(N2CCCCC2)nc(N)n1"),
    ("azathioprine_core", "Cn1cnc([N+](=O)[O-])c1Sc1ncnc2nc[nH]c12"),
    ("uric_acid", "O=c1[nH]c(=O)c2[nH]c(=O)[nH]c2[nH]1"),
    ("pemetrexed_core", "Nc1nc2[nH]cc(CCc3ccc(C(=O)O)cc3)c2c(=O)[nH]1"),
    ("tadalafil", "CN1CC(=O)N2C(Cc3c([nH]c4ccccc34)C2c2ccc3c(c2)OCO3)C1=O"),
    ("linezolid", "CC(=O)NCC1CN(c2ccc(N3CCOCC3)c(F)c2)C(=O)O1"),
    ("mycophenolic_core", "COc1c(C)c2c(c(O)c1CC=C(C)CCC(=O)O)C(=O)OC2"),
    ("entacapone", "CCN(CC)C(=O)C(C#N)=Cc1cc(O)c(O)c([N+](=O)[O-])c1")
]


def vina_types(sdf_text):
    """(AD type, has HD, position) of each heavy atom in Open Babel's PDBQT."""
    mol = pybel.readstring("sdf", sdf_text)
    text = mol.write("pdbqt")
    atoms = []
    for line in text.splitlines():
        if line.startswith(("ATOM", "HETATM")):
            xyz = np.array([float(line[30:38]), float(line[38:46]), float(line[46:54])])
            atoms.append((line[77:79].strip(), xyz))
    out = []
    for t, x in atoms:
        if t in ("H", "HD"):
            continue
        hd = any(u == "HD" and np.linalg.norm(x - y) < 1.15 for u, y in atoms)
        out.append((t, hd, x))
    return out


def xs(ad, hd):
    return {"N": "N_D" if hd else "N_P", "NA": "N_DA" if hd else "N_A",
            "OA": "O_DA" if hd else "O_A"}.get(ad)


def main():
    os.makedirs(DATA, exist_ok=True)
    ob.obErrorLog.SetOutputLevel(0)
    rdBase.DisableLog("rdApp.*")
    out = []
    for name, smiles in MOLECULES:
        mol = Chem.AddHs(Chem.MolFromSmiles(smiles))
        AllChem.EmbedMolecule(mol, randomSeed=7)
        AllChem.MMFFOptimizeMolecule(mol)
        conf = mol.GetConformer()
        ref = vina_types(Chem.MolToMolBlock(mol))
        heavy = [a for a in mol.GetAtoms() if a.GetAtomicNum() > 1]
        types = {}
        with open(os.path.join(DATA, name + ".pdb"), "w") as f:
            f.write("REMARK   %s\n" % smiles)
            for k, a in enumerate(heavy):
                p = conf.GetAtomPosition(a.GetIdx())
                el = a.GetSymbol()
                atom = (el + str(k + 1))[:4]
                q = a.GetFormalCharge()
                # The charge in columns 79-80 (as 1- or 2+), where there is one.
                charge = "%d%s" % (abs(q), "+" if q > 0 else "-") if q else ""
                f.write("HETATM%5d %-4s LIG A   1    %8.3f%8.3f%8.3f  1.00  0.00          %2s%s\n"
                        % (k + 1, atom, p.x, p.y, p.z, el.upper(), charge))
                if el in ("N", "O"):
                    x = np.array([p.x, p.y, p.z])
                    ad, hd, _ = min(ref, key=lambda r: np.linalg.norm(r[2] - x))
                    types[atom] = xs(ad, hd)
            f.write("END\n")
        out.append({"name": name, "smiles": smiles, "file": "tests/data/perception/%s.pdb" % name,
                    "types": types})
    meta = {"made_by": "tests/reference/perception/make_perception.py",
            "rdkit": rdBase.rdkitVersion, "openbabel": ob.OBReleaseVersion(),
            "molecules": out}
    with open(os.path.join(HERE, "values.json"), "w") as f:
        json.dump(meta, f, indent=1)
        f.write("\n")
    print("%d molecules" % len(out))


if __name__ == "__main__":
    main()
