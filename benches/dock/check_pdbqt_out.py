#!/usr/bin/env python3
"""Reads `bump dock -o OUT.pdbqt` with AutoDock Vina 1.2 itself: each
`MODEL` block is given to Vina as a ligand (its parser checks the torsion
tree and the atom types) and scored in place (`score()`, maps over the
model plus 10 Å); Vina's total must equal the model's `REMARK VINA RESULT`
within 0.01 kcal/mol.

    bump dock R.pdbqt L.pdbqt --box-from REF -o out.pdbqt
    python3 benches/dock/check_pdbqt_out.py R.pdbqt out.pdbqt
"""
import sys

from vina import Vina


def blocks(text):
    cur = None
    for line in text.splitlines():
        if line.startswith("MODEL"):
            cur = []
        elif line.startswith("ENDMDL"):
            yield cur
            cur = None
        elif cur is not None:
            cur.append(line)


def main():
    receptor, out = sys.argv[1], sys.argv[2]
    bad = n = 0
    for k, lines in enumerate(blocks(open(out).read())):
        n += 1
        remark = next(l for l in lines if l.startswith("REMARK VINA RESULT:"))
        bump_total = float(remark.split(":")[1].split()[0])
        xyz = [(float(l[30:38]), float(l[38:46]), float(l[46:54])) for l in lines if l.startswith(("ATOM", "HETATM"))]
        lo = [min(p[i] for p in xyz) for i in range(3)]
        hi = [max(p[i] for p in xyz) for i in range(3)]
        v = Vina(sf_name="vina", verbosity=0)
        v.set_receptor(receptor)
        v.set_ligand_from_string("\n".join(lines) + "\n")
        v.compute_vina_maps(center=[(a + b) / 2 for a, b in zip(lo, hi)], box_size=[b - a + 10 for a, b in zip(lo, hi)])
        vina_total = v.score()[0]
        ok = abs(vina_total - bump_total) <= 0.01
        bad += not ok
        print(f"model {k + 1}: bump {bump_total:.3f} vina {vina_total:.3f} {'ok' if ok else 'DIFFERS'}")
    print(f"{n} models read by Vina, {bad} differ")
    sys.exit(1 if bad or n == 0 else 0)


if __name__ == "__main__":
    main()
