#!/usr/bin/env python3
"""Python module overhead (docs/performance.md, "Python module"): batched FK of 10^5
configurations through armstudy.Design.fk against the C++ loop (fk_loop) at the same thread
count, and the overhead of one single-configuration call. Run on demand:
    cmake --build build --target bench_python
"""
import argparse
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np

import armstudy

ap = argparse.ArgumentParser()
ap.add_argument("--loop", required=True, help="the fk_loop executable")
ap.add_argument("--design", required=True)
ap.add_argument("--configurations", type=int, default=100_000)
ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
args = ap.parse_args()

d = armstudy.load_design(args.design)
rng = np.random.default_rng(1)
q = d.lower + rng.random((args.configurations, d.dof)) * (d.upper - d.lower)


def median_time(fn, repeats):
    t = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        t.append(time.perf_counter() - t0)
    return statistics.median(t)


with tempfile.TemporaryDirectory() as tmp:
    path = os.path.join(tmp, "q.f64")
    q.tofile(path)
    print(f"design {d.name} ({d.dof} joints), {args.configurations} configurations")
    print(f"{'threads':>7s} {'C++ loop [ms]':>14s} {'Python fk [ms]':>15s} {'ratio':>6s}")
    one_cpp = None
    for t in args.threads:
        out = subprocess.run([args.loop, args.design, path, str(t)], capture_output=True, text=True,
                             check=True).stdout.split()
        cpp_s, one = float(out[0]), float(out[1])
        one_cpp = one if one_cpp is None else min(one_cpp, one)
        py_s = median_time(lambda: d.fk(q, threads=t), 15)
        print(f"{t:7d} {cpp_s * 1e3:14.2f} {py_s * 1e3:15.2f} {py_s / cpp_s:6.2f}")

calls = 100_000
q1 = q[0].copy()
per_call = median_time(lambda: [d.fk(q1) for _ in range(calls)], 5) / calls
print(f"single configuration: Python fk {per_call * 1e6:.2f} us per call, C++ forwardKinematics "
      f"{one_cpp * 1e6:.2f} us: overhead {(per_call - one_cpp) * 1e6:.2f} us")
