#!/usr/bin/env python3
"""Estimates link inertial data for the shipped designs (docs/dynamics.md, "Inertial data").

The thesis gives no masses or inertias, so every number printed here is an ASSUMPTION built from
the kinematic tables and plausible component masses:

  * link i = aluminium tube (density 2700 kg/m^3) on the straight line from the origin of frame i
    to the origin of frame i+1 (or to the TCP for the last link), plus the drive module of joint
    i+1 that link i carries, modelled as a solid cylinder centred on the origin of frame i+1 with
    its axis along joint i+1's z axis;
  * module masses and sizes per motor/gear type of Tables A.1 and A.2 (dictionary MODULES below);
  * the last link also carries a flange; the end-effector is the [payload] at the TCP.

Usage: python3 scripts/estimate_inertia.py designs/final_prototype_9dof.toml
prints the [[inertia]] and [payload] sections that are appended to the design file.
"""
import math
import sys
import tomllib

RHO_AL = 2700.0  # kg/m^3

# Drive modules: (mass kg, radius m, length m). Assumed, see docs/dynamics.md.
MODULES = {
    # final prototype, Table A.2 (TQ RoboDrive + Harmonic Drive units with housing and electronics)
    "A": (2.3, 0.055, 0.12),   # ILM 85x13 + CPL-32
    "B": (1.1, 0.040, 0.09),   # ILM 50x08 + CSD-20
    "C": (0.55, 0.030, 0.07),  # ILM 38x06 + CSD-14
    # first prototype, Table A.1 (Maxon/Emoteq motors + Harmonic Drive gears)
    "EC-i-40+CSD-17": (0.9, 0.040, 0.10),
    "EC-45+CSG-25": (1.6, 0.050, 0.11),
    "EC-max-40+CSD-20": (1.1, 0.040, 0.10),
    "EC-i-40+CSD-14": (0.7, 0.035, 0.09),
    "EC-45-flat+CSD-14": (0.6, 0.035, 0.07),
    "HT01001+CSD-14": (0.5, 0.030, 0.07),
    "HT00801+HFUC-8": (0.3, 0.022, 0.06),
}

# Per design: module carried at the distal end of each link (the drive of the next joint), tube
# outer diameter and wall per link, lift carriage mass, flange mass and the payload.
DESIGNS = {
    "final_prototype_9dof": {
        "next_module": ["A", "A", "A", "B", "B", "C", "C", "C", None],
        "tube": [(0.08, 0.003)] * 4 + [(0.06, 0.003)] * 2 + [(0.04, 0.002)] * 3,
        "carriage": 1.5, "flange": 0.15, "payload": (1.2, [0.0, 0.0, 0.08], "harvesting end-effector 1.0 kg + fruit 0.2 kg, COM 0.08 m beyond the TCP"),
    },
    "final_prototype_7dof": {
        "next_module": ["A", "A", "A", "C", "C", "C", None],
        "tube": [(0.08, 0.003)] * 4 + [(0.04, 0.002)] * 3,
        "carriage": 1.5, "flange": 0.15, "payload": (1.2, [0.0, 0.0, 0.08], "harvesting end-effector 1.0 kg + fruit 0.2 kg, COM 0.08 m beyond the TCP"),
    },
    "first_prototype_9dof": {
        "next_module": ["EC-i-40+CSD-17", "EC-45+CSG-25", "EC-45+CSG-25", "EC-max-40+CSD-20",
                        "EC-i-40+CSD-14", "EC-45-flat+CSD-14", "HT01001+CSD-14", "HT00801+HFUC-8", None],
        "tube": [(0.07, 0.003)] * 4 + [(0.05, 0.003)] * 2 + [(0.04, 0.002)] * 3,
        "carriage": 1.5, "flange": 0.1, "payload": (1.2, [0.0, 0.0, 0.08], "harvesting end-effector 1.0 kg + fruit 0.2 kg, COM 0.08 m beyond the TCP"),
    },
    "first_prototype_6dof": {
        "next_module": ["EC-i-40+CSD-17", "EC-45+CSG-25", "EC-45+CSG-25", "EC-max-40+CSD-20",
                        "EC-i-40+CSD-14", None],
        "tube": [(0.07, 0.003)] * 4 + [(0.05, 0.003)] + [(0.03, 0.002)],
        "carriage": 1.5, "flange": 0.1, "payload": (0.3, [0.0, 0.0, 0.0], "spray nozzle with valve and hose end"),
    },
}


def q(v):
    if isinstance(v, (int, float)):
        return float(v)
    s = v.strip()
    scale = 1.0
    for unit, f in (("deg", math.pi / 180), ("mm", 1e-3), ("m", 1.0)):
        if s.endswith(unit):
            s, scale = s[: -len(unit)].strip(), f
            break
    return eval(s, {"pi": math.pi}) * scale


def matmul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def rot(a, b, g):
    ca, sa, cb, sb, cg, sg = math.cos(a), math.sin(a), math.cos(b), math.sin(b), math.cos(g), math.sin(g)
    Rx = [[1, 0, 0], [0, ca, -sa], [0, sa, ca]]
    Ry = [[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]]
    Rz = [[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]]
    return matmul(matmul(Rx, Ry), Rz)


def axis_body(m, c, u, i_axis, i_perp):
    """Body with COM c, symmetry axis u: returns (m, c, I about COM)."""
    n = math.sqrt(sum(x * x for x in u))
    u = [x / n for x in u] if n > 0 else [0.0, 0.0, 1.0]
    I = [[(i_axis - i_perp) * u[r] * u[k] + (i_perp if r == k else 0.0) for k in range(3)] for r in range(3)]
    return (m, c, I)


def combine(bodies):
    m = sum(b[0] for b in bodies)
    c = [sum(b[0] * b[1][k] for b in bodies) / m for k in range(3)]
    I = [[0.0] * 3 for _ in range(3)]
    for bm, bc, bI in bodies:
        d = [bc[k] - c[k] for k in range(3)]
        d2 = sum(x * x for x in d)
        for r in range(3):
            for k in range(3):
                I[r][k] += bI[r][k] + bm * ((d2 if r == k else 0.0) - d[r] * d[k])
    return m, c, I


def main(path):
    with open(path, "rb") as fh:
        design = tomllib.load(fh)
    name = design["design"]["name"]
    spec = DESIGNS[name]
    joints = design["joint"]
    n = len(joints)
    tcp = [q(design["tcp"].get(k, 0.0)) for k in ("x", "y", "z")]
    out = []
    for i, jt in enumerate(joints):
        bodies = []
        if i + 1 < n:
            nxt = joints[i + 1]
            end = [q(nxt[k]) for k in ("x", "y", "z")]
            axis_next = [row[2] for row in rot(q(nxt["alpha"]), q(nxt["beta"]), q(nxt["gamma"]))]
        else:
            end = tcp
            axis_next = None
        L = math.sqrt(sum(x * x for x in end))
        D, t = spec["tube"][i]
        if L > 1e-9:
            Ro, Ri = D / 2, D / 2 - t
            m_tube = RHO_AL * math.pi * (Ro * Ro - Ri * Ri) * L
            bodies.append(axis_body(m_tube, [x / 2 for x in end], end,
                                    m_tube / 2 * (Ro * Ro + Ri * Ri),
                                    m_tube / 12 * (3 * (Ro * Ro + Ri * Ri) + L * L)))
        mod = spec["next_module"][i]
        if mod:
            mm, r, l = MODULES[mod]
            bodies.append(axis_body(mm, end, axis_next, mm * r * r / 2, mm * (3 * r * r + l * l) / 12))
        if i == 0 and jt["type"] == "prismatic":
            mc = spec["carriage"]  # lift carriage, a 0.15 m cube at the frame origin
            bodies.append(axis_body(mc, [0.0, 0.0, 0.0], [0, 0, 1], mc * 0.15**2 / 6, mc * 0.15**2 / 6))
        if i == n - 1:
            mf = spec["flange"]  # output flange, disc r = 0.03 m, 0.01 m thick on z
            bodies.append(axis_body(mf, [0.0, 0.0, 0.005], [0, 0, 1], mf * 0.03**2 / 2,
                                    mf * (3 * 0.03**2 + 0.01**2) / 12))
        m, c, I = combine(bodies)
        c = [0.0 if abs(x) < 1e-12 else x for x in c]
        I = [[0.0 if abs(x) < 1e-12 else x for x in row] for row in I]
        desc = []
        if L > 1e-9:
            desc.append(f"Al tube D{D*1000:.0f}x{t*1000:.0f} mm, {L:.3f} m")
        if mod:
            desc.append(f"module {mod} of the next joint")
        if i == 0 and jt["type"] == "prismatic":
            desc.append("lift carriage")
        if i == n - 1:
            desc.append("flange")
        out.append("[[inertia]]   # assumption: " + "; ".join(desc))
        out.append(f'link = "{jt["name"]}"')
        out.append(f"mass = {m:.4f}")
        out.append("com = [%.5f, %.5f, %.5f]" % tuple(c))
        out.append("inertia = [%.6g, %.6g, %.6g, %.6g, %.6g, %.6g]   # Ixx, Iyy, Izz, Ixy, Ixz, Iyz about the COM"
                   % (I[0][0], I[1][1], I[2][2], I[0][1], I[0][2], I[1][2]))
        out.append("")
    pm, pc, pdesc = spec["payload"]
    out.append(f"[payload]   # assumption: {pdesc}, a point mass in the TCP frame")
    out.append(f"mass = {pm}")
    out.append("com = [%g, %g, %g]" % tuple(pc))
    print("\n".join(out))


if __name__ == "__main__":
    main(sys.argv[1])
