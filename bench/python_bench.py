#!/usr/bin/env python3
"""The Python and multi-core figures of REPORT.md.

Usage: PYTHONPATH=build/python python3 bench/python_bench.py DIR [BENCH_BINARY]

Runs the C++ batches first (BENCH_BINARY, default build/bench/minksum_bench, its Batch/ rows into
DIR/batch.json), then times from Python the same workloads (bench/batch_bench.cpp's, built the
same way here), one right after the other so that the machine's speed is the same for both: each
batch on 1 and 2 threads, a single coherent query per call, and the sums of the paper's Table 1
pairs against SciPy's ConvexHull of the pairwise sums (Qhull, which a Python user would reach
for), and each workload's ceiling on this machine (two processes running the 1-thread batch at
once). Writes DIR/python.md. Each figure, C++ or Python, is the best of five repeats, the 1- and
2-thread runs taken in turn; the batches refill one result (out=), as the C++ rows reuse theirs.
"""
import json
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import ConvexHull

import minksum

PHI = (1 + 5 ** 0.5) / 2


def loop(n, f):
    """Calls f n times, keeping only the last answer."""
    for _ in range(n):
        f()


def best(f, repeat=5):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def turn(axis, angle):
    """Rodrigues' rotation about a unit axis."""
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def orbit(n, lift):
    """bench/batch_bench.cpp's orbit: n poses round the origin, turning about z."""
    t = np.arange(n) / n
    poses = np.tile(np.eye(4), (n, 1, 1))
    c, s = np.cos(9 * t), np.sin(9 * t)
    poses[:, 0, 0], poses[:, 0, 1], poses[:, 1, 0], poses[:, 1, 1] = c, -s, s, c
    poses[:, 0, 3], poses[:, 1, 3], poses[:, 2, 3] = 2.5 * np.cos(40 * t), 2.5 * np.sin(30 * t), lift + 0.4 * np.sin(7 * t)
    return poses


def cyclic(a, b):
    return [p for s in (-a, a) for u in (-b, b) for p in ((0, s, u), (s, u, 0), (u, 0, s))]


CUBE = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
ICOSAHEDRON = np.array(cyclic(1, PHI), float)
DODECAHEDRON = np.vstack([CUBE, cyclic(1 / PHI, PHI)])


def sheet():
    xs = -4 + 0.125 * np.arange(65)
    x, y = np.meshgrid(xs, xs, indexing="ij")
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.2 * np.sin(0.5 * x.ravel() + y.ravel())])
    c = (np.arange(64)[:, None] * 65 + np.arange(64)[None, :]).ravel()
    triangles = np.vstack([np.column_stack([c, c + 65, c + 1]), np.column_stack([c + 1, c + 65, c + 66])])
    return minksum.Mesh(vertices, triangles)


def batches():
    """Per workload: (name, items, the batch as a function of threads and the result to refill)."""
    box, unit_box = minksum.Shape.box((0.5, 0.5, 0.5)), minksum.Shape.box()
    icosahedron, ball, mesh = minksum.Shape.from_points(ICOSAHEDRON), minksum.Shape.sphere(0.3), sheet()
    p100k, from20k, to20k, lift20k, p5k = orbit(100000, 0), orbit(20000, 3), orbit(20000, -3), orbit(20000, 1), orbit(5000, 0)
    boxes, icosahedra = [box] * 5000, [icosahedron] * 5000
    return [
        ("proximity", 100000, lambda th, out: minksum.proximity_batch(box, None, icosahedron, p100k, threads=th, out=out)),
        ("time_of_impact", 20000,
         lambda th, out: minksum.time_of_impact_batch(unit_box, None, None, ball, from20k, to20k, threads=th, out=out)),
        ("mesh_distance", 20000, lambda th, out: minksum.mesh_distance_batch(mesh, None, ball, lift20k, threads=th, out=out)),
        ("sum", 5000, lambda th, out: minksum.minkowski_sum_batch(boxes, None, icosahedra, p5k, threads=th)),
    ]


def single_query_ns():
    """One coherent proximity call per pose from Python, as a loop of single calls would."""
    box, icosahedron = minksum.Shape.box((0.5, 0.5, 0.5)), minksum.Shape.from_points(ICOSAHEDRON)
    poses = orbit(100000, 0)[:20000]
    cache = minksum.ProximityCache()

    def run():
        for p in poses:
            minksum.proximity(box, None, icosahedron, p, cache=cache)
    return 1e9 * best(run) / len(poses)


def table1_rows():
    r = turn((1, 2, 3), 0.7)
    pairs = [("cube_rotcube", CUBE, CUBE), ("cube_icosa", CUBE, ICOSAHEDRON), ("icosa_icosa", ICOSAHEDRON, ICOSAHEDRON),
             ("cube_dodeca", CUBE, DODECAHEDRON), ("dodeca_dodeca", DODECAHEDRON, DODECAHEDRON),
             ("icosa_dodeca", ICOSAHEDRON, DODECAHEDRON)]
    rows = []
    for name, a, b in pairs:
        b = b @ r.T
        sa, sb = minksum.Shape.from_points(a), minksum.Shape.from_points(b)
        repeats, kept = 2000, minksum.minkowski_sum(sa, None, sb, None)
        # Each answer replaces the last, as in a loop that uses one sum at a time, on both sides
        # (a list of 2,000 results would time this VM's fresh pages, up to 10 us each, instead).
        fresh = best(lambda: loop(repeats, lambda: minksum.minkowski_sum(sa, None, sb, None))) / repeats
        reused = best(lambda: loop(repeats, lambda: minksum.minkowski_sum(sa, None, sb, None, out=kept))) / repeats
        theirs = best(lambda: loop(200, lambda: ConvexHull((a[:, None, :] + b[None, :, :]).reshape(-1, 3)))) / 200
        rows.append((name, kept.F, fresh * 1e6, reused * 1e6, theirs * 1e6))
    return rows


def ms_of(benchmark):
    return benchmark["real_time"] * {"ns": 1e-6, "us": 1e-3, "ms": 1, "s": 1e3}[benchmark["time_unit"]]


def cpp_rows(directory, binary):
    """Runs the C++ Batch/ rows, five repetitions each interleaved at random (a slow spell of this
    machine then falls on every row alike): (name, threads) -> the best, ms per batch."""
    subprocess.run([binary, "--benchmark_filter=^Batch/", "--benchmark_min_time=0.2", "--benchmark_repetitions=5",
                    "--benchmark_enable_random_interleaving=true", f"--benchmark_out={directory}/batch.json",
                    "--benchmark_out_format=json"], check=True, stdout=subprocess.DEVNULL)
    with open(f"{directory}/batch.json") as f:
        run = json.load(f)
    out = {}
    for b in run["benchmarks"]:
        if b["name"].startswith("Batch/") and b.get("run_type", "iteration") == "iteration":
            parts = b["name"].split("/")
            key = (parts[1], int(parts[2].split(":")[1]))
            out[key] = min(out.get(key, float("inf")), ms_of(b))
    return out


def two_processes(binary, name):
    """The machine's own ceiling for 2 threads on a workload: two processes, each running the
    1-thread C++ batch at the same time (sharing nothing but the machine), against one alone
    right before: their combined throughput over its, the median of three rounds."""
    def ms_per_batch(copies):
        command = [binary, f"--benchmark_filter=^Batch/{name}/threads:1/", "--benchmark_min_time=0.3",
                   "--benchmark_format=json"]
        runs = [subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL) for _ in range(copies)]
        return [ms_of(json.loads(r.communicate()[0])["benchmarks"][0]) for r in runs]
    ratios = []
    for _ in range(3):
        alone = ms_per_batch(1)[0]
        ratios.append(sum(alone / t for t in ms_per_batch(2)))
    return sorted(ratios)[1]


def main(directory, binary="build/bench/minksum_bench"):
    cpp = cpp_rows(directory, binary)
    lines = ["### Batches on 1 and 2 threads (ms per batch; the same workloads, C++ and Python, in the same run)", "",
             "The machine's ceiling: two processes each running the 1-thread C++ batch at once, their combined throughput "
             "over one's alone (nothing shared but the machine).", "",
             "| workload | items | C++, 1 thread | C++, 2 threads | C++ 2 / 1 threads (target >= 1.8x) "
             "| the machine's ceiling | Python, 1 thread | Python / C++, 1 thread (target <= 1.2x) | Python, 2 threads "
             "| Python 2 / 1 threads |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    per_item_cpp = {}
    for name, items, run in batches():
        # As the C++ rows reuse their results, the batches refill theirs (out=): no new memory.
        out = run(1, None)
        times = {1: [], 2: []}
        for _ in range(5):  # (1 and 2 threads in turn, as the C++ rows are interleaved)
            for threads in (1, 2):
                start = time.perf_counter()
                run(threads, out)
                times[threads].append(time.perf_counter() - start)
        one, two = min(times[1]), min(times[2])
        c1, c2 = cpp.get((name, 1)), cpp.get((name, 2))
        per_item_cpp[name] = c1 * 1e6 / items if c1 else None
        cell = lambda x: f"{x:.2f}" if x else "-"
        lines.append(f"| {name} | {items:,} | {cell(c1)} | {cell(c2)} | {c1 / c2:.2f}x | {two_processes(binary, name):.2f}x | "
                     f"{one * 1e3:.2f} | {one * 1e3 / c1:.2f}x | {two * 1e3:.2f} | {one / two:.2f}x |" if c1 and c2 else
                     f"| {name} | {items:,} | - | - | - | - | {one * 1e3:.2f} | - | {two * 1e3:.2f} | {one / two:.2f}x |")
    single = single_query_ns()
    base = per_item_cpp.get("proximity")
    lines += ["", "### One coherent query from Python (ns per call)", "",
              "| Python, one call per pose | C++, per item of the 1-thread batch | Python's overhead (target <= 1000 ns) |",
              "|---|---|---|",
              f"| {single:.0f} | {base:.0f} | {single - base:.0f} |" if base else f"| {single:.0f} | - | - |"]
    lines += ["", "### Table 1 from Python: minksum.minkowski_sum against SciPy's ConvexHull of the pairwise sums (us per sum)", "",
              "Prepared shapes; a new Sum per call, or one refilled (out=, as the C++ rows reuse theirs); each answer replaces the last, on both sides.", "",
              "| pair | facets | minksum, new Sum | minksum, out= | scipy ConvexHull | ConvexHull / new Sum | "
              "ConvexHull / out= (target >= 50x) |",
              "|---|---|---|---|---|---|---|"]
    for name, facets, fresh, reused, theirs in table1_rows():
        lines.append(f"| {name} | {facets} | {fresh:.2f} | {reused:.2f} | {theirs:.1f} | {theirs / fresh:.0f}x | {theirs / reused:.0f}x |")
    with open(f"{directory}/python.md", "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main(*sys.argv[1:])
