#!/usr/bin/env python3
"""Times gemmi reading structure files, the peer bump's loader is held to.

For each file: the time of `gemmi.read_structure` in this process (min and
median of several runs, after one warm-up run), its atom count, and a
whole-process run (`python -c "import gemmi; gemmi.read_structure(...)"`)
timed from start to exit, with its peak resident size (`/usr/bin/time -v`
when present). Prints one JSON object per file, which the benchmark
report's loading section reads (benches/load.rs).

Usage: gemmi_load.py [--runs N] FILE...
"""

import json
import os
import statistics
import subprocess
import sys
import time


def process_run(path):
    """Wall seconds, peak RSS (KiB, or None) and CPU seconds (user + system,
    or None) of a fresh process reading path."""
    code = "import gemmi, sys; gemmi.read_structure(sys.argv[1])"
    cmd = [sys.executable, "-c", code, path]
    timer = "/usr/bin/time"
    rss = None
    cpu = None
    start = time.perf_counter()
    if os.access(timer, os.X_OK):
        done = subprocess.run([timer, "-v"] + cmd, capture_output=True, text=True)
        wall = time.perf_counter() - start
        for line in done.stderr.splitlines():
            if "Maximum resident set size" in line:
                rss = int(line.split(":")[1])
            elif "User time (seconds)" in line or "System time (seconds)" in line:
                cpu = (cpu or 0.0) + float(line.split(":")[1])
    else:
        subprocess.run(cmd, check=True)
        wall = time.perf_counter() - start
    return wall, rss, cpu


def main(argv):
    import gemmi

    runs = 5
    files = []
    it = iter(argv)
    for a in it:
        if a == "--runs":
            runs = int(next(it))
        else:
            files.append(a)
    for path in files:
        st = gemmi.read_structure(path)  # warm-up: the file in the page cache
        atoms = st[0].count_atom_sites() if len(st) else 0
        times = []
        cpu_times = []
        for _ in range(runs):
            t0 = time.perf_counter()
            c0 = time.process_time()
            gemmi.read_structure(path)
            times.append(time.perf_counter() - t0)
            cpu_times.append(time.process_time() - c0)
        procs = [process_run(path) for _ in range(max(1, runs // 2))]
        walls = sorted(p[0] for p in procs)
        rss = [p[1] for p in procs if p[1] is not None]
        cpus = [p[2] for p in procs if p[2] is not None]
        print(
            json.dumps(
                {
                    "file": os.path.basename(path),
                    "gemmi": gemmi.__version__,
                    "atoms_first_model": atoms,
                    "read_s_min": min(times),
                    "read_s_median": statistics.median(times),
                    "read_cpu_s_min": min(cpu_times),
                    "process_s_min": walls[0],
                    "process_s_median": statistics.median(walls),
                    "process_max_rss_kib": max(rss) if rss else None,
                    "process_cpu_s_min": min(cpus) if cpus else None,
                }
            ),
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:])
