"""Inverse dynamics and the mass matrix against `armstudy dynamics --json`; self-collision
distances against a brute-force distance of points sampled on the volumes' cores."""
import itertools
import json
import unittest

import numpy as np

import armstudy
from support import cli, design_path, random_configurations

DYNAMICS_TOLERANCE = 1e-12   # relative: the same code, JSON round-trips doubles exactly
SPACING_M = 0.002            # gap between the points sampled on a core in the brute force
TRIANGLE_SAMPLES = 40        # points per edge of a triangle core
# The brute force lies above the exact distance by at most half the sampling gap on each core.
BRUTE_SLACK_M = SPACING_M


class Dynamics(unittest.TestCase):
    def test_inverse_dynamics_and_mass_matrix_equal_the_cli(self):
        for name in ["final_prototype_7dof", "first_prototype_9dof"]:
            d = armstudy.load_design(design_path(name))
            rng = np.random.default_rng(7)
            q = random_configurations(d, 3, seed=8)
            qd = rng.normal(size=q.shape)
            qdd = rng.normal(size=q.shape)
            tau = d.inverse_dynamics(q, qd, qdd, threads=2)
            M = d.mass_matrix(q)
            for i in range(len(q)):
                args = ["dynamics", design_path(name), "--json", "--mass-matrix"]
                for flag, v in (("--q", q[i]), ("--qd", qd[i]), ("--qdd", qdd[i])):
                    args.append(flag + "=" + ",".join(repr(x) for x in v))
                _, out, _ = cli(*args)
                j = json.loads(out)
                Q = np.array([row["Q"] for row in j["joints"]])
                np.testing.assert_allclose(tau[i], Q, rtol=DYNAMICS_TOLERANCE, atol=1e-12)
                np.testing.assert_allclose(M[i], np.array(j["mass_matrix"]), rtol=DYNAMICS_TOLERANCE,
                                           atol=1e-12)
            # Static: gravity only.
            g = d.inverse_dynamics(q)
            np.testing.assert_allclose(g, d.inverse_dynamics(q, np.zeros_like(q), np.zeros_like(q)))


def core_points(volume, T):
    """Points sampled on a volume's core (a point, a segment, a triangle), in W."""
    p = volume["points"]
    if len(p) == 1:
        pts = p
    elif len(p) == 2:
        count = max(2, int(np.ceil(np.linalg.norm(p[1] - p[0]) / SPACING_M)) + 1)
        t = np.linspace(0.0, 1.0, count)[:, None]
        pts = p[0] + t * (p[1] - p[0])
    else:
        uv = [(u, v) for u in np.linspace(0, 1, TRIANGLE_SAMPLES) for v in np.linspace(0, 1, TRIANGLE_SAMPLES) if u + v <= 1]
        pts = np.array([p[0] + u * (p[1] - p[0]) + v * (p[2] - p[0]) for u, v in uv])
    return pts @ T[:3, :3].T + T[:3, 3]


class SelfCollision(unittest.TestCase):
    def test_pair_distances_match_a_brute_force(self):
        d = armstudy.load_design(design_path("final_prototype_9dof"))
        pairs = d.collision_pairs
        self.assertGreater(len(pairs), 0)
        q = random_configurations(d, 10, seed=9)
        D = d.self_distances(q, threads=2)
        self.assertEqual(D.shape, (10, len(pairs)))
        F = d.frames(q)
        base = np.eye(4)
        from support import rot_xyz
        b = d.base
        base[:3, :3] = rot_xyz(b["alpha"], b["beta"], b["gamma"])
        base[:3, 3] = [b["x"], b["y"], b["z"]]
        index = {n: k for k, n in enumerate(d.joint_names)}
        for i in range(len(q)):
            def frame(body):
                return base if body == "base" else F[i, index[body]]
            for k, (a, bname) in enumerate(pairs):
                best = np.inf
                for va, vb in itertools.product([v for v in d.volumes if v["link"] == a],
                                                [v for v in d.volumes if v["link"] == bname]):
                    pa, pb = core_points(va, frame(a)), core_points(vb, frame(bname))
                    dist = np.min(np.linalg.norm(pa[:, None, :] - pb[None, :, :], axis=2))
                    best = min(best, dist - va["radius"] - vb["radius"])
                self.assertGreaterEqual(best + 1e-12, D[i, k], msg=f"{a}-{bname}")
                self.assertLess(best - D[i, k], BRUTE_SLACK_M, msg=f"{a}-{bname}")


if __name__ == "__main__":
    unittest.main()
