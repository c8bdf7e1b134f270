#!/usr/bin/env python3
"""`bump dock` beside AutoDock Vina 1.2 in one run, complex by complex
(bump first, then Vina, so both see the same machine load): the same box
(the crystal ligand + 5 Å, at least 20 Å), the same random start file, the
same thread count and exhaustiveness. Vina's top pose is rescored exactly by
`bump score`, so both top-1 scores come from the same evaluator.

    python3 benches/dock/compare.py ../shared/dock OUT.md [--cpu 2] [--seeds 1]

Writes a Markdown table to OUT.md and the raw records to OUT.md.jsonl.
"""
import argparse, json, os, statistics, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(__file__))
from vina_dock import box_of, heavy_coords, models, rmsd  # noqa: E402
from vina import Vina  # noqa: E402

BUMP = os.environ.get("BUMP", "target/release/bump")


def bump_dock(d, cpu, seed, ex):
    cmd = [BUMP, "dock", f"{d}/protein.pdbqt", f"{d}/rand-0.pdbqt", "--box-from", f"{d}/flex-xray.pdbqt",
           "--reference", f"{d}/flex-xray.pdbqt", "--cpu", str(cpu), "--seed", str(seed),
           "--exhaustiveness", str(ex), "--json"]
    t0 = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    m = json.loads(r.stdout)["molecules"][0]
    p = m["poses"]
    return {"wall_s": wall, "top_score": p[0]["total"], "top_rmsd": p[0]["rmsd_to_reference"],
            "best_rmsd": min(x["rmsd_to_reference"] for x in p), "collides": any(x["collides"] for x in p),
            "poses": len(p)}


def bump_score(protein, pose_text):
    with tempfile.NamedTemporaryFile("w", suffix=".pdbqt", delete=False) as f:
        f.write(pose_text)
        path = f.name
    try:
        r = subprocess.run([BUMP, "score", protein, path, "--json"], capture_output=True, text=True, check=True)
        return json.loads(r.stdout)["total"]
    finally:
        os.unlink(path)


def vina_dock(d, cpu, seed, ex):
    xray = heavy_coords(open(f"{d}/flex-xray.pdbqt").read())
    centre, size = box_of(xray)
    t0 = time.perf_counter()
    v = Vina(sf_name="vina", cpu=cpu, seed=seed, verbosity=0)
    v.set_receptor(f"{d}/protein.pdbqt")
    v.set_ligand_from_file(f"{d}/rand-0.pdbqt")
    v.compute_vina_maps(center=centre, box_size=size)
    v.dock(exhaustiveness=ex, n_poses=9)
    wall = time.perf_counter() - t0
    poses = models(v.poses(n_poses=9))
    rms = [rmsd(heavy_coords(p), xray) for p in poses]
    return {"wall_s": wall, "top_score_vina": v.energies(n_poses=1)[0][0],
            "top_score": bump_score(f"{d}/protein.pdbqt", poses[0]), "top_rmsd": rms[0], "best_rmsd": min(rms)}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("set")
    ap.add_argument("out")
    ap.add_argument("--cpu", type=int, default=2)
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--exhaustiveness", type=int, default=8)
    ap.add_argument("--only", default="")
    a = ap.parse_args()
    ids = sorted(x for x in os.listdir(a.set) if os.path.isdir(os.path.join(a.set, x)))
    if a.only:
        ids = [i for i in ids if i in a.only.split(",")]
    recs = []
    with open(a.out + ".jsonl", "w") as raw:
        for cid in ids:
            d = os.path.join(a.set, cid)
            for seed in [int(s) for s in a.seeds.split(",")]:
                b = bump_dock(d, a.cpu, seed, a.exhaustiveness)
                v = vina_dock(d, a.cpu, seed, a.exhaustiveness)
                rec = {"id": cid, "seed": seed, "bump": b, "vina": v}
                recs.append(rec)
                raw.write(json.dumps(rec) + "\n")
                raw.flush()
                print(f"{cid} seed {seed}: bump {b['wall_s']:.1f} s {b['top_score']:.2f} {b['top_rmsd']:.2f} Å | "
                      f"vina {v['wall_s']:.1f} s {v['top_score']:.2f} {v['top_rmsd']:.2f} Å", file=sys.stderr)
    lines = ["| complex | seed | bump top-1 RMSD (Å) | best of 9 | Vina top-1 RMSD | best of 9 | bump top-1 score | Vina top-1 score | bump s | Vina s |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in recs:
        b, v = r["bump"], r["vina"]
        lines.append(f"| {r['id']} | {r['seed']} | {b['top_rmsd']:.2f} | {b['best_rmsd']:.2f} | {v['top_rmsd']:.2f} | "
                     f"{v['best_rmsd']:.2f} | {b['top_score']:.3f} | {v['top_score']:.3f} | {b['wall_s']:.1f} | {v['wall_s']:.1f} |")
    n = len(recs)
    ok = lambda k: sum(1 for r in recs if r[k]["top_rmsd"] <= 2.0)
    ratio = statistics.median(r["bump"]["wall_s"] / r["vina"]["wall_s"] for r in recs)
    within = sum(1 for r in recs if r["bump"]["top_score"] <= r["vina"]["top_score"] + 0.1)
    lines += ["", f"Top-1 success (≤ 2 Å): bump {ok('bump')}/{n}, Vina {ok('vina')}/{n}. "
              f"Median time ratio bump/Vina: {ratio:.2f}. bump's top-1 score at or below Vina's + 0.1 kcal/mol: {within}/{n}. "
              f"Poses that collide: {sum(1 for r in recs if r['bump']['collides'])}."]
    open(a.out, "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
