"""Point-triangle continuous collision detection by ipctk (the Incremental Potential Contact
toolkit, ipc-sim/ipc-toolkit), for the cross-check of our vertex-face CCD (issue 8).

Each query is a point moving on a straight line and a triangle whose corners move on straight
lines over one step, t in [0, 1]. ipctk's Tight-Inclusion CCD (Wang et al., "A Large Scale
Benchmark and an Inclusion-Based Algorithm for Continuous Collision Detection", ACM TOG 40(5),
2021) is conservative: when it answers "no impact", there is none; an "impact" may be a false
positive only where the point comes within about `tolerance` of the triangle.

A query whose point starts within `tolerance` of the triangle is not passed to the CCD: ipctk then
shrinks Tight-Inclusion's tolerance to half the initial distance and, for a time of impact below
1e-6, reruns it without an iteration limit (`TightInclusionCCD::ccd_strategy`,
src/ipc/ccd/tight_inclusion_ccd.cpp), which for a point lying in the face (the distance 1e-16)
exhausts memory. Such a query is answered "in contact at t = 0" by ipctk's own rule for an initial
distance within the minimum separation (`check_initial_distance`), measured with ipctk's
`point_triangle_distance`, and flagged in `initial`.

We call it with `conservative_rescaling = 1`: ipctk's default (0.8) moves the time of impact
earlier on purpose, to keep IPC's line search away from contact; here we want the first time of
contact itself. The tolerance and iteration cap are ipctk's defaults unless the request says
otherwise.

Request (JSON): {"queries_file": path (absolute, or relative to this folder), "count": n,
"tolerance": 1e-6, "max_iterations": 10000000, "conservative_rescaling": 1.0, ...}
The file holds the queries in the binary format of `harness/crosscheck/ccd_queries.rs`: the magic
b"CCDQ0001", a little-endian u64 count, then per query a u8 source code and 24 little-endian f64:
v_t0, f0_t0, f1_t0, f2_t0, v_t1, f0_t1, f1_t1, f2_t1 (x, y, z each).

Answer (JSON): {"provenance": {...}, "settings": {...}, "seconds": s,
"hit": [0 or 1 per query], "toi": [time of impact, or null where no hit],
"initial": [1 where the point starts within `tolerance` of the triangle (answered t = 0 without
the CCD), else 0], "initial_distance": [ipctk's point-triangle distance at t = 0]}
"""

import datetime
import importlib.metadata
import json
import os
import platform
import sys
import time

import numpy as np

HEADER = 16
QUERY = np.dtype([("source", "u1"), ("x", "<f8", (8, 3))])


def read_queries(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"CCDQ0001":
        raise ValueError(f"{path}: not a CCD query file (magic {data[:8]!r})")
    count = int.from_bytes(data[8:16], "little")
    if len(data) != HEADER + count * QUERY.itemsize:
        raise ValueError(
            f"{path}: {len(data)} bytes, expected {HEADER + count * QUERY.itemsize} for {count} queries"
        )
    return np.frombuffer(data, dtype=QUERY, offset=HEADER, count=count)


def provenance():
    packages = {name: importlib.metadata.version(name) for name in ("ipctk", "numpy")}
    return {
        "script": "ipctk_ccd.py",
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "python": platform.python_version(),
        "packages": packages,
    }


def run(request):
    import ipctk

    req = json.loads(request)
    path = req["queries_file"]
    if not os.path.isabs(path):
        path = os.path.join(os.path.dirname(os.path.abspath(__file__)), path)
    queries = read_queries(path)
    if "count" in req and req["count"] != len(queries):
        raise ValueError(f"{path}: {len(queries)} queries, the request says {req['count']}")
    settings = {
        "tolerance": float(req.get("tolerance", ipctk.TightInclusionCCD.DEFAULT_TOLERANCE)),
        "max_iterations": int(req.get("max_iterations", ipctk.TightInclusionCCD.DEFAULT_MAX_ITERATIONS)),
        "conservative_rescaling": float(req.get("conservative_rescaling", 1.0)),
        "min_distance": 0.0,
        "tmax": 1.0,
        "method": "ipctk.TightInclusionCCD.point_triangle_ccd",
    }
    ccd = ipctk.TightInclusionCCD(
        tolerance=settings["tolerance"],
        max_iterations=settings["max_iterations"],
        conservative_rescaling=settings["conservative_rescaling"],
    )
    hits, tois, initial, distances = [], [], [], []
    start = time.perf_counter()
    for q in queries:
        x = [np.ascontiguousarray(p) for p in q["x"]]
        d0 = float(np.sqrt(ipctk.point_triangle_distance(x[0], x[1], x[2], x[3])))
        distances.append(d0)
        if d0 <= settings["tolerance"]:
            hits.append(1)
            tois.append(0.0)
            initial.append(1)
            continue
        hit, toi = ccd.point_triangle_ccd(*x, min_distance=0.0, tmax=1.0)
        hits.append(1 if hit else 0)
        tois.append(float(toi) if hit else None)
        initial.append(0)
    seconds = time.perf_counter() - start
    print(f"ipctk_ccd: {len(queries)} queries, {sum(hits)} hits, {seconds:.2f} s", file=sys.stderr)
    return json.dumps(
        {
            "provenance": provenance(),
            "settings": settings,
            "seconds": seconds,
            "hit": hits,
            "toi": tois,
            "initial": initial,
            "initial_distance": distances,
        }
    )


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        print(run(f.read()))
