#!/usr/bin/env python3
"""`bump dock` beside AutoDock Vina 1.2 and QuickVina 2.1 in one run, complex
by complex (bump, then Vina, then QuickVina, so all see about the same
machine load): the same box
(the crystal ligand + 5 Å, at least 20 Å), the same random start file, the
same thread count and exhaustiveness. The peers' top poses are rescored
exactly by `bump score`, so every top-1 score comes from the same evaluator.
QuickVina 2.1 runs when `--qvina PATH` names its binary (built from
`QVina/qvina`, branch `qvina2`, `build/linux/release`, against Debian's
Boost, with `-std=c++14` for `-ansi` and without `-static`).

    python3 benches/dock/compare.py ../shared/dock OUT.md [--cpu 2] [--seeds 1,2,3] \
        [--qvina PATH] [--pocket-box]

`--pocket-box` also docks bump in the box of the top-ranked pocket
(`--pocket 1`) instead of the crystal ligand's.

Writes a Markdown table to OUT.md and the raw records to OUT.md.jsonl.
"""
import argparse, json, os, statistics, subprocess, sys, tempfile, time

sys.path.insert(0, os.path.dirname(__file__))
from vina_dock import box_of, heavy_coords, models, rmsd  # noqa: E402
from vina import Vina  # noqa: E402

BUMP = os.environ.get("BUMP", "target/release/bump")


def bump_dock(d, cpu, seed, ex, pocket=False):
    box = ["--pocket", "1"] if pocket else ["--box-from", f"{d}/flex-xray.pdbqt"]
    cmd = [BUMP, "dock", f"{d}/protein.pdbqt", f"{d}/rand-0.pdbqt", *box,
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


def qvina_dock(binary, d, cpu, seed, ex):
    xray = heavy_coords(open(f"{d}/flex-xray.pdbqt").read())
    centre, size = box_of(xray)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.pdbqt")
        cmd = [binary, "--receptor", f"{d}/protein.pdbqt", "--ligand", f"{d}/rand-0.pdbqt",
               "--center_x", str(centre[0]), "--center_y", str(centre[1]), "--center_z", str(centre[2]),
               "--size_x", str(size[0]), "--size_y", str(size[1]), "--size_z", str(size[2]),
               "--exhaustiveness", str(ex), "--cpu", str(cpu), "--seed", str(seed),
               "--num_modes", "9", "--out", out]
        t0 = time.perf_counter()
        subprocess.run(cmd, capture_output=True, text=True, check=True)
        wall = time.perf_counter() - t0
        poses = models(open(out).read())
    rms = [rmsd(heavy_coords(p), xray) for p in poses]
    return {"wall_s": wall, "top_score": bump_score(f"{d}/protein.pdbqt", poses[0]),
            "top_rmsd": rms[0], "best_rmsd": min(rms)}


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
    ap.add_argument("--qvina", default="")
    ap.add_argument("--pocket-box", action="store_true")
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
                if a.qvina:
                    rec["qvina"] = qvina_dock(a.qvina, d, a.cpu, seed, a.exhaustiveness)
                if a.pocket_box:
                    rec["bump_pocket"] = bump_dock(d, a.cpu, seed, a.exhaustiveness, pocket=True)
                recs.append(rec)
                raw.write(json.dumps(rec) + "\n")
                raw.flush()
                line = (f"{cid} seed {seed}: bump {b['wall_s']:.1f} s {b['top_score']:.2f} {b['top_rmsd']:.2f} Å | "
                        f"vina {v['wall_s']:.1f} s {v['top_score']:.2f} {v['top_rmsd']:.2f} Å")
                for k in ("qvina", "bump_pocket"):
                    if k in rec:
                        q = rec[k]
                        line += f" | {k} {q['wall_s']:.1f} s {q['top_score']:.2f} {q['top_rmsd']:.2f} Å"
                print(line, file=sys.stderr)
    tools = ["bump", "vina"] + [k for k in ("qvina", "bump_pocket") if a.qvina and k == "qvina" or a.pocket_box and k == "bump_pocket"]
    head = "| complex | seed | " + " | ".join(f"{t} top-1 RMSD (Å) | {t} best of 9 | {t} top-1 score | {t} s" for t in tools) + " |"
    lines = [head, "|---|---:|" + "---:|" * (4 * len(tools))]
    for r in recs:
        cells = []
        for t in tools:
            x = r[t]
            cells += [f"{x['top_rmsd']:.2f}", f"{x['best_rmsd']:.2f}", f"{x['top_score']:.3f}", f"{x['wall_s']:.1f}"]
        lines.append(f"| {r['id']} | {r['seed']} | " + " | ".join(cells) + " |")
    n = len(recs)
    lines.append("")
    for t in tools:
        ok = sum(1 for r in recs if r[t]["top_rmsd"] <= 2.0)
        ratio = statistics.median(r[t]["wall_s"] / r["vina"]["wall_s"] for r in recs)
        lines.append(f"- {t}: top-1 success (≤ 2 Å) {ok}/{n}; median time / Vina's {ratio:.2f}")
    within = sum(1 for r in recs if r["bump"]["top_score"] <= r["vina"]["top_score"] + 0.1)
    lines.append(f"- bump's top-1 score at or below Vina's + 0.1 kcal/mol: {within}/{n}; poses that collide: "
                 f"{sum(1 for r in recs if r['bump']['collides'])}")
    # Reliability: per complex, are the top-1 poses of every seed within 2 Å of the first seed's?
    seeds = sorted({r["seed"] for r in recs})
    if len(seeds) > 1:
        for t in tools:
            same = 0
            ids = sorted({r["id"] for r in recs})
            for cid in ids:
                tops = [r[t]["top_rmsd"] for r in recs if r["id"] == cid]
                # Same pose within 2 Å: all found the crystal pose, or all missed it by the same margin.
                same += all(x <= 2.0 for x in tops) or max(tops) - min(tops) <= 2.0 and all(x > 2.0 for x in tops)
            lines.append(f"- {t}: the same top-1 pose over {len(seeds)} seeds on {same}/{len(ids)} complexes")
    open(a.out, "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
