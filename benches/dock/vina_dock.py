#!/usr/bin/env python3
"""AutoDock Vina 1.2 beside `bump dock`: docks each complex of a set with
Vina's Python API on the box the benchmark uses (the crystal ligand's
heavy-atom extent plus 5 Å on every side, at least 20 Å along each axis),
from the random start file, and prints one JSON line per complex and seed:
the time, the top pose's Vina score and heavy-atom RMSD to the crystal pose
(atoms in file order, as the set's files share it), the best RMSD of the
poses, and the poses themselves (PDBQT text) for bump to rescore.

    python3 benches/dock/vina_dock.py ../shared/dock OUT.jsonl \
        [--exhaustiveness 8] [--cpu 2] [--seeds 1,2] [--only 1hnn,1yv3]
"""
import argparse, json, math, os, sys, time

from vina import Vina


def heavy_coords(pdbqt_text):
    out = []
    for line in pdbqt_text.splitlines():
        if line.startswith(("ATOM", "HETATM")):
            t = line[77:79].strip()
            if t in ("H", "HD", "HS"):
                continue
            out.append((float(line[30:38]), float(line[38:46]), float(line[46:54])))
    return out


def rmsd(a, b):
    n = min(len(a), len(b))
    if n == 0:
        return float("nan")
    return math.sqrt(sum((p[0]-q[0])**2 + (p[1]-q[1])**2 + (p[2]-q[2])**2 for p, q in zip(a, b)) / n)


def box_of(coords, pad=5.0, min_size=20.0):
    lo = [min(c[i] for c in coords) for i in range(3)]
    hi = [max(c[i] for c in coords) for i in range(3)]
    centre = [(l + h) / 2 for l, h in zip(lo, hi)]
    size = [max(h - l + 2 * pad, min_size) for l, h in zip(lo, hi)]
    return centre, size


def models(text):
    out, cur = [], []
    for line in text.splitlines():
        if line.startswith("MODEL"):
            cur = []
        elif line.startswith("ENDMDL"):
            out.append("\n".join(cur) + "\n")
        else:
            cur.append(line)
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("set")
    ap.add_argument("out")
    ap.add_argument("--exhaustiveness", type=int, default=8)
    ap.add_argument("--cpu", type=int, default=2)
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--only", default="")
    ap.add_argument("--start", default="rand-0.pdbqt")
    a = ap.parse_args()
    ids = sorted(d for d in os.listdir(a.set) if os.path.isdir(os.path.join(a.set, d)))
    if a.only:
        ids = [i for i in ids if i in a.only.split(",")]
    with open(a.out, "w") as out:
        for cid in ids:
            d = os.path.join(a.set, cid)
            xray = heavy_coords(open(os.path.join(d, "flex-xray.pdbqt")).read())
            centre, size = box_of(xray)
            for seed in [int(s) for s in a.seeds.split(",")]:
                v = Vina(sf_name="vina", cpu=a.cpu, seed=seed, verbosity=0)
                t0 = time.perf_counter()
                v.set_receptor(os.path.join(d, "protein.pdbqt"))
                v.set_ligand_from_file(os.path.join(d, a.start))
                v.compute_vina_maps(center=centre, box_size=size)
                v.dock(exhaustiveness=a.exhaustiveness, n_poses=9)
                elapsed = time.perf_counter() - t0
                text = v.poses(n_poses=9)
                poses = models(text)
                energies = v.energies(n_poses=9)
                rms = [rmsd(heavy_coords(p), xray) for p in poses]
                rec = {
                    "id": cid, "seed": seed, "elapsed_s": elapsed,
                    "box_center": centre, "box_size": size,
                    "top_score": energies[0][0] if len(energies) else None,
                    "top_rmsd": rms[0] if rms else None,
                    "best_rmsd": min(rms) if rms else None,
                    "scores": [e[0] for e in energies],
                    "poses": poses,
                }
                out.write(json.dumps(rec) + "\n")
                out.flush()
                print(f"{cid} seed {seed}: {elapsed:.1f} s top {rec['top_score']:.2f} rmsd {rec['top_rmsd']:.2f} best {rec['best_rmsd']:.2f}", file=sys.stderr)


if __name__ == "__main__":
    main()
