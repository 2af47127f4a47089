#!/usr/bin/env python3
"""Compares two designs on the thesis Fig. 3.8 spraying row from Python (docs/python.md): the
6-DoF first prototype and the 7-DoF final prototype, as one study built as a dict and run by the
engine (the same files as `armstudy run`), then a table of what each reaches and how dexterously,
and a figure of the two status maps when matplotlib is installed.

    PYTHONPATH=build/python python3 studies/compare_designs.py [--step 0.05] [--output output]
"""
import argparse
import os
import sys

import numpy as np

import armstudy

HERE = os.path.dirname(os.path.abspath(__file__))
DESIGNS = ["first_prototype_6dof", "final_prototype_7dof"]


def study(step_m):
    """The Fig. 3.8 row (eq. 3.3) at a coarser step, both designs, the spraying task (eq. 3.1)."""
    return {
        "study": {"name": "compare_designs_py",
                  "description": "6-DoF first vs 7-DoF final prototype on the Fig. 3.8 spraying row"},
        "design": [{"file": f"../designs/{d}.toml"} for d in DESIGNS],
        "reach": {"task_space": "spraying", "position_tolerance": "1 mm",
                  "orientation_tolerance": "0.5 deg",
                  "grid": [{"name": "fig3_8",
                            "x": {"from": "-0.78 m", "to": "0.78 m", "step": f"{step_m} m"},
                            "y": {"from": "0.3 m", "to": "1.2 m", "step": f"{step_m} m"},
                            "z": "1.2 m", "alpha": "0 deg", "gamma": ["-40 deg", "40 deg"]}]},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--step", type=float, default=0.05, help="grid step [m] (the thesis: 0.01)")
    ap.add_argument("--output", default="output", help="folder that receives compare_designs_py/")
    ap.add_argument("--threads", type=int, default=0, help="threads (0 = all cores)")
    args = ap.parse_args()

    run = armstudy.run_study(study(args.step), output=args.output, threads=args.threads,
                             overwrite=True, folder=HERE)
    print(f"study {run['study']} -> {run['output_dir']}")
    print(f"{'design':24s} {'dof':>3s} {'reachable':>9s} {'mean manip.':>11s} {'p5 manip.':>9s}"
          f" {'centre pose':>11s}")
    maps = {}
    for name in DESIGNS:
        design = armstudy.load_design(os.path.join(HERE, "..", "designs", name + ".toml"))
        key = f"reach/fig3_8/{name}"
        m = run["metrics"]
        # The kernel layer next to the study: the centre pose of the row solved directly.
        centre = design.solve([0.0, 0.75, 1.2, 0.0, 0.0, np.radians(40)], "spraying")
        print(f"{name:24s} {design.dof:3d} {m[key + '/reachable_fraction']:9.1%} "
              f"{m[key + '/manipulability_mean']:11.4f} {m[key + '/manipulability_p5']:9.4f}"
              f" {centre['status_name']:>11s}")
        maps[name] = run["maps"][f"reach/fig3_8/{name}.vti"]

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib is not installed: the table above is the comparison)")
        return 0
    fig, axes = plt.subplots(1, len(DESIGNS), figsize=(5 * len(DESIGNS), 3.5), sharey=True)
    for ax, name in zip(axes, DESIGNS):
        mp = maps[name]
        status = [k for k in mp["arrays"] if k.startswith("status")][0]
        x, y = mp["axes"]["x"], mp["axes"]["y"]
        ax.pcolormesh(x, y, mp["arrays"][status][0] == 0, shading="nearest", cmap="Greens")
        ax.set_title(f"{name}: {status}")
        ax.set_xlabel("x [m]")
    axes[0].set_ylabel("y [m]")
    path = os.path.join(run["output_dir"], "compare_designs_py.png")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    print(f"figure: {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
