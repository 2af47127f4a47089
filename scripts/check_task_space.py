#!/usr/bin/python3
"""Checks a study's stored reach maps against an independent forward kinematics.

For every spraying grid (task space x,y,z,alpha,gamma) of a study's output folder and every
design in designs.json, at each reachable pose's stored joint values q (the .vti array q):
  - FK from the design's kinematic table in designs.json (written here from the thesis' row
    transform Trans * Rx * Ry * Rz, Appendix B; not armstudy's code) gives the tool axis
    R_WT * tool_axis; its angle to the spray direction d = Rx(alpha) Rz(gamma) e_y is reported;
  - the Jacobian by central differences of that FK (position columns, and the angular columns
    from the rotation log) gives sqrt(det(J_t J_t^T)) of the 3 position rows and the 2 angular
    rows perpendicular to the tool axis; its relative difference to the stored manipulability
    is reported.
Prints one line per grid and design: poses checked, largest axis angle [deg], largest relative
manipulability difference. Exit 1 when an angle exceeds --tolerance-deg or a difference exceeds
--rel times the value plus --abs.

Needs VTK's Python module (Debian python3-vtk9); run with /usr/bin/python3:
    /usr/bin/python3 scripts/check_task_space.py output/compare_designs
"""
import argparse
import json
import math
import os
import sys

import vtk  # Debian python3-vtk9


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def rot_x(t):
    c, s = math.cos(t), math.sin(t)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def rot_y(t):
    c, s = math.cos(t), math.sin(t)
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]]


def rot_z(t):
    c, s = math.cos(t), math.sin(t)
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def row_transform(p):
    """Trans(x, y, z) * Rx(alpha) * Ry(beta) * Rz(gamma) of a designs.json pose entry."""
    r = mat_mul(mat_mul(rot_x(p["alpha_rad"]), rot_y(p["beta_rad"])), rot_z(p["gamma_rad"]))
    return r, [p["x_m"], p["y_m"], p["z_m"]]


def compose(a, b):
    ra, pa = a
    rb, pb = b
    return mat_mul(ra, rb), [pa[i] + mat_vec(ra, pb)[i] for i in range(3)]


def fk(design, q):
    """TCP pose (R, p) in the task frame W: base, then per joint its row and the joint motion."""
    t = row_transform(design["base"])
    for j, qi in zip(design["joints"], q):
        t = compose(t, row_transform(j))
        if j["type"] == "revolute":
            t = compose(t, (rot_z(qi), [0, 0, 0]))
        else:
            t = compose(t, ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0, 0, qi]))
    return compose(t, row_transform(design["tcp"]))


def rotation_log(r):
    """Rotation vector of a rotation matrix close to the identity."""
    c = max(-1.0, min(1.0, (r[0][0] + r[1][1] + r[2][2] - 1) / 2))
    a = math.acos(c)
    v = [r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1]]
    f = 0.5 if a < 1e-12 else a / (2 * math.sin(a))
    return [f * x for x in v]


def det(m):
    """Determinant by Gaussian elimination with partial pivoting."""
    a = [row[:] for row in m]
    n = len(a)
    d = 1.0
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(a[r][c]))
        if a[p][c] == 0:
            return 0.0
        if p != c:
            a[c], a[p] = a[p], a[c]
            d = -d
        d *= a[c][c]
        for r in range(c + 1, n):
            f = a[r][c] / a[c][c]
            for k in range(c, n):
                a[r][k] -= f * a[c][k]
    return d


def measure(rows):
    g = [[sum(x * y for x, y in zip(a, b)) for b in rows] for a in rows]
    return math.sqrt(max(0.0, det(g)))


def unit_orthogonal(a):
    # Any unit vector perpendicular to a (the determinant does not depend on the choice).
    k = min(range(3), key=lambda i: abs(a[i]))
    e = [0, 0, 0]
    e[k] = 1
    dot = sum(x * y for x, y in zip(e, a))
    v = [e[i] - dot * a[i] for i in range(3)]
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def task_manipulability(design, q, axis_w, h=1e-6):
    r0, _ = fk(design, q)
    cols = []
    for i in range(len(q)):
        qp, qm = list(q), list(q)
        qp[i] += h
        qm[i] -= h
        rp, pp = fk(design, qp)
        rm, pm = fk(design, qm)
        v = [(pp[k] - pm[k]) / (2 * h) for k in range(3)]
        # omega: log(R(q + h) R(q - h)^T) / (2 h), in W
        rt = [[rm[j][i2] for j in range(3)] for i2 in range(3)]
        w = [x / (2 * h) for x in rotation_log(mat_mul(rp, rt))]
        cols.append((v, w))
    b1 = unit_orthogonal(axis_w)
    b2 = cross(axis_w, b1)
    rows = [[c[0][k] for c in cols] for k in range(3)]
    rows.append([sum(b1[k] * c[1][k] for k in range(3)) for c in cols])
    rows.append([sum(b2[k] * c[1][k] for k in range(3)) for c in cols])
    return measure(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("output", help="a study's output folder, e.g. output/compare_designs")
    ap.add_argument("--tolerance-deg", type=float, default=0.5, help="largest allowed axis angle [deg]")
    ap.add_argument("--rel", type=float, default=1e-6, help="largest allowed relative manipulability difference")
    ap.add_argument("--abs", type=float, default=1e-9,
                    help="absolute floor of the allowed difference: central differences carry ~1e-10 of rounding "
                         "per Jacobian entry, which dominates at (near-)singular poses")
    ap.add_argument("--every", type=int, default=1, help="check every n-th reachable pose (speed)")
    ap.add_argument("--axis", action="append", default=[], metavar="DESIGN=X,Y,Z",
                    help="tool axis of a design in its TCP frame, for outputs whose designs.json has none")
    a = ap.parse_args()
    designs = {d["name"]: d for d in json.load(open(os.path.join(a.output, "designs.json")))}
    for spec in a.axis:
        name, _, xyz = spec.rpartition("=")
        designs[name]["tool_axis"] = [float(v) for v in xyz.split(",")]
    summary = json.load(open(os.path.join(a.output, "summary.json")))
    ok = True
    for grid in summary["reach"]["grids"]:
        if grid["task_space"] != "x,y,z,alpha,gamma":
            continue
        for entry in grid["designs"]:
            name = entry["design"]
            design = designs[name]
            axis_t = design["tool_axis"]
            reader = vtk.vtkXMLImageDataReader()
            reader.SetFileName(os.path.join(a.output, entry["vti"]))
            reader.Update()
            pd = reader.GetOutput().GetPointData()
            n_o = len(grid["orientations"])
            worst_deg, worst_rel, checked, seen, over = 0.0, 0.0, 0, 0, False
            for k, o in enumerate(grid["orientations"]):
                sfx = "_o%d" % k if n_o > 1 else ""
                status, qa, wa = pd.GetArray("status" + sfx), pd.GetArray("q" + sfx), pd.GetArray("manipulability" + sfx)
                al, ga = o["alpha_rad"], o["gamma_rad"]
                d = [-math.sin(ga), math.cos(al) * math.cos(ga), math.sin(al) * math.cos(ga)]
                for p in range(status.GetNumberOfTuples()):
                    if status.GetTuple1(p) != 0:
                        continue
                    seen += 1
                    if (seen - 1) % a.every:
                        continue
                    q = list(qa.GetTuple(p))
                    r, _ = fk(design, q)
                    axis_w = mat_vec(r, axis_t)
                    c = max(-1.0, min(1.0, sum(x * y for x, y in zip(axis_w, d))))
                    worst_deg = max(worst_deg, math.degrees(math.acos(c)))
                    w = task_manipulability(design, q, axis_w)
                    diff = abs(wa.GetTuple1(p) - w)
                    worst_rel = max(worst_rel, diff / max(w, 1e-300))
                    over |= diff > a.rel * w + a.abs
                    checked += 1
            bad = worst_deg > a.tolerance_deg + 1e-9 or over
            ok &= not bad
            print("%s %s %s: %d of %d reachable poses checked, largest axis angle %.6f deg, largest relative "
                  "manipulability difference %.2e%s" % (os.path.basename(os.path.normpath(a.output)), grid["name"],
                                                         name, checked, seen, worst_deg, worst_rel,
                                                         "  FAIL" if bad else ""))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
