"""Benchmark: `cagd deviation` on a large scan, serial against ``--workers N`` (issue 16,
scan scale).

A bicubic 8 x 8 B-spline patch (z = 2 sin(x/15) cos(y/20) over [0, 100]^2, written as a
JSON model) and N points near it (uniform over the patch's box, z offset N(0, 0.5)) in a
CSV; ``python -m cagd.cli deviation`` runs in a child process once per worker count, with
the per-point CSV (``--csv``). Prints per run the wall time and the peak resident memory
of the command and its worker processes together (the sum over the process tree,
sampled every 0.2 s from /proc: Linux only; elsewhere the largest single process from
``getrusage``) and their CPU time, and checks that every run wrote the first run's CSV
and report byte for byte. With ``--repeat R`` the worker counts alternate R times and
the fastest run of each is shown (on a shared machine the load of others varies).

Run: python -m benchmarks.deviation_workers [--points N] [--workers 1 2] [--repeat R] [--keep DIR]
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import List, Optional, Tuple

import numpy as np

#: rows of the scan written per block (the text of 10^7 rows at once would be ~1 GB)
BLOCK = 1 << 20


def write_inputs(folder: Path, points: int, seed: int = 0) -> Tuple[Path, Path]:
    """The model (one bicubic patch) and a scan of ``points`` points near it."""
    u = np.linspace(0.0, 100.0, 8)
    U, V = np.meshgrid(u, u, indexing="ij")
    P = np.stack([U, V, 2.0 * np.sin(U / 15.0) * np.cos(V / 20.0)], -1)
    model = folder / "patch.json"
    model.write_text(json.dumps({"format": "cagd-model", "version": 1, "objects": [
        {"name": "patch", "type": "bspline_surface", "degree_u": 3, "degree_v": 3,
         "control_points": P.tolist()}]}))
    rng = np.random.default_rng(seed)
    scan = folder / "scan.csv"
    with open(scan, "w") as f:
        f.write("x,y,z\n")
        for s in range(0, points, BLOCK):
            n = min(BLOCK, points - s)
            X = np.column_stack([rng.uniform(0, 100, n), rng.uniform(0, 100, n), rng.normal(0, 0.5, n)])
            np.savetxt(f, X, delimiter=",", fmt="%.17g")
    return model, scan


def _tree_rss(pid: int) -> int:
    """Resident bytes of the process ``pid`` and all its descendants (/proc)."""
    children = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    parent = int(f.read().rsplit(")", 1)[1].split()[1])
                children.setdefault(parent, []).append(int(entry))
            except (OSError, ValueError, IndexError):
                pass
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        todo += children.get(p, [])
        try:
            with open(f"/proc/{p}/status") as f:
                total += next(int(ln.split()[1]) * 1024 for ln in f if ln.startswith("VmRSS:"))
        except (OSError, StopIteration):
            pass
    return total


def run(model: Path, scan: Path, out: Path, workers: int) -> Tuple[float, float, Optional[int]]:
    """(wall seconds, CPU seconds, peak resident bytes of the process tree) of one command."""
    out.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, "-m", "cagd.cli", "deviation", str(model), str(scan), "-o", "r.md", "--csv", "r.csv",
           "--workers", str(workers), "--no-progress"]
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=out, stdout=subprocess.DEVNULL)
    peak: List[int] = [0]
    linux = os.path.isdir("/proc/self")

    def sample() -> None:
        while proc.poll() is None:
            peak[0] = max(peak[0], _tree_rss(proc.pid))
            time.sleep(0.2)

    watcher = threading.Thread(target=sample, daemon=True)
    if linux:
        watcher.start()
    code = proc.wait()
    wall = time.perf_counter() - t0
    if linux:
        watcher.join()
    if code != 0:
        raise SystemExit(f"{' '.join(cmd)} exited {code}")
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)      # the command and its reaped workers
    cpu = cpu1.ru_utime + cpu1.ru_stime - cpu0.ru_utime - cpu0.ru_stime
    if not linux:
        peak[0] = cpu1.ru_maxrss * 1024
    return wall, cpu, peak[0] or None


def _digest(path: Path) -> str:
    """SHA-256 of a file, read 16 MiB at a time (the per-point CSV of 10^7 points is 2 GB)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 24), b""):
            h.update(block)
    return h.hexdigest()


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2], help="worker counts (the first is the "
                                                                           "reference)")
    ap.add_argument("--repeat", type=int, default=1, help="runs per worker count, alternating (the fastest "
                                                          "is shown: the machine may be shared)")
    ap.add_argument("--keep", type=Path, help="write the inputs and outputs here (default: a temporary folder)")
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        folder = a.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        t0 = time.perf_counter()
        model, scan = write_inputs(folder, a.points)
        print(f"{a.points:,} points near a bicubic 8 x 8 patch (scan written in {time.perf_counter() - t0:.1f} s); "
              f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f} at the start")
        print(f"{'workers':>8s} {'wall s':>9s} {'speed-up':>9s} {'CPU s':>8s} {'peak RSS MB':>12s}  outputs")
        ok = True
        reference: Optional[Tuple[str, str]] = None
        best = {}
        for _ in range(a.repeat):
            for w in a.workers:
                out = folder / f"w{w}"
                wall, cpu, rss = run(model, scan, out, w)
                digests = (_digest(out / "r.csv"), _digest(out / "r.md"))
                if reference is None:
                    reference = digests
                same = digests == reference
                ok &= same
                print(f"  (workers {w}: {wall:.1f} s)", flush=True)
                if w not in best or wall < best[w][0]:
                    best[w] = (wall, cpu, rss, same)
        for w in a.workers:
            wall, cpu, rss, same = best[w]
            rss_text = "n/a" if rss is None else f"{rss / 2 ** 20:.0f}"
            text = "byte for byte the first run's" if same else "DIFFERENT from the first run's"
            print(f"{w:8d} {wall:9.1f} {best[a.workers[0]][0] / wall:9.2f} {cpu:8.1f} {rss_text:>12s}  {text}",
                  flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
