"""Times AutoDock Vina 1.2 (the `vina` Python package) beside bump's scoring
benchmarks: grid maps for cubes at 0.375 A and `optimize` from the crystal
pose, for trimethoprim in DHFR. Prints one JSON object.

Usage: python3 vina_times.py RECEPTOR.pdb VALUES.json COMPLEX_ID [REPS]

The receptor PDBQT is written from the PDB's polymer heavy atoms with
element-based AutoDock types (no hydrogens, zero charges): enough for
timing, whose cost depends on the atoms near the box, not on their types.
The ligand is the PDBQT the reference recorded (values.json).
"""
import json
import os
import sys
import tempfile
import time

from vina import Vina

AD = {"C": "C", "N": "N", "O": "OA", "S": "SA", "P": "P"}


def receptor_pdbqt(pdb):
    out = []
    for line in open(pdb):
        if not line.startswith("ATOM"):
            continue
        el = (line[76:78].strip() or line[12:14].strip()).capitalize()
        if el == "H":
            continue
        out.append("%s%6.3f %-2s" % (line[:54].ljust(54) + "  1.00  0.00    ", 0.0, AD.get(el, "C")))
    return "\n".join(out) + "\n"


def best(reps, f):
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    times.sort()
    return times[0], times[len(times) // 2]


def main():
    pdb, values, cid = sys.argv[1:4]
    reps = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    cx = json.load(open(values))["complexes"][cid]
    with tempfile.TemporaryDirectory() as d:
        rec = os.path.join(d, "rec.pdbqt")
        open(rec, "w").write(receptor_pdbqt(pdb))
        v = Vina(sf_name="vina", cpu=0, verbosity=0)
        v.set_receptor(rec)
        pose = cx["ligand"]["pdbqt"]
        if isinstance(pose, list):
            pose = "\n".join(pose) + "\n"
        v.set_ligand_from_string(pose)
        centre = cx["ligand"]["heavy_centroid"]
        out = {"threads": os.cpu_count()}
        for side in (20.0, 24.0):
            mn, md = best(reps, lambda: v.compute_vina_maps(center=centre, box_size=[side] * 3, spacing=0.375))
            out["maps_%d_ms" % side] = [mn * 1e3, md * 1e3]
        v.compute_vina_maps(center=centre, box_size=[24.0] * 3, spacing=0.375)
        # The recorded pose, set again before each optimize.

        times = []
        for _ in range(max(reps, 20)):
            v.set_ligand_from_string(pose)
            t0 = time.perf_counter()
            v.optimize(0)
            times.append(time.perf_counter() - t0)
        times.sort()
        out["optimize_ms"] = [times[0] * 1e3, times[len(times) // 2] * 1e3]
        print(json.dumps(out))


main()
