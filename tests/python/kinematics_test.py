"""FK and Jacobians of the Python module against orocos-kdl (python3-pykdl, a chain built here
from the design's joint table), against the armstudy CLI's `fk --json`, and the task Jacobian and
manipulability against their definition on the KDL Jacobian."""
import json
import unittest

import numpy as np
import PyKDL as kdl

import armstudy
from support import DESIGNS, cli, design_path, random_configurations, rot_xyz

FK_TOLERANCE = 1e-12        # KDL and armstudy compose the same transforms in another order
MANIP_TOLERANCE = 1e-12     # relative, sqrt(det) of the same rows
CONFIGURATIONS = 200


def kdl_frame(p):
    r = rot_xyz(p["alpha"], p["beta"], p["gamma"])
    return kdl.Frame(kdl.Rotation(*r.flatten()), kdl.Vector(p["x"], p["y"], p["z"]))


def kdl_chain(design):
    """Base placement, then per joint its fixed offset and a joint about / along the new z axis."""
    chain = kdl.Chain()
    fixed = kdl_frame(design.base)
    for j in design.joints:
        fixed = fixed * kdl_frame(j)
        kind = kdl.Joint.RotZ if j["type"] == "revolute" else kdl.Joint.TransZ
        chain.addSegment(kdl.Segment(kdl.Joint(kdl.Joint.Fixed), fixed))
        chain.addSegment(kdl.Segment(kdl.Joint(kind), kdl.Frame.Identity()))
        fixed = kdl.Frame.Identity()
    chain.addSegment(kdl.Segment(kdl.Joint(kdl.Joint.Fixed), kdl_frame(design.tcp)))
    return chain


def kdl_fk_and_jacobian(chain, q):
    n = len(q)
    qa = kdl.JntArray(n)
    for i in range(n):
        qa[i] = q[i]
    f = kdl.Frame()
    kdl.ChainFkSolverPos_recursive(chain).JntToCart(qa, f)
    jac = kdl.Jacobian(n)
    kdl.ChainJntToJacSolver(chain).JntToJac(qa, jac)
    T = np.eye(4)
    T[:3, :3] = np.array([[f.M[r, c] for c in range(3)] for r in range(3)])
    T[:3, 3] = [f.p[0], f.p[1], f.p[2]]
    J = np.array([[jac[r, c] for c in range(n)] for r in range(6)])
    return T, J


class KinematicsAgainstKdl(unittest.TestCase):
    def test_fk_and_jacobian_equal_kdl(self):
        for name in DESIGNS:
            d = armstudy.load_design(design_path(name))
            chain = kdl_chain(d)
            q = random_configurations(d, CONFIGURATIONS, seed=1)
            T = d.fk(q, threads=2)
            J = d.jacobian(q, threads=2)
            self.assertEqual(T.shape, (CONFIGURATIONS, 4, 4))
            self.assertEqual(J.shape, (CONFIGURATIONS, 6, d.dof))
            for i in range(CONFIGURATIONS):
                T_kdl, J_kdl = kdl_fk_and_jacobian(chain, q[i])
                np.testing.assert_allclose(T[i], T_kdl, rtol=0, atol=FK_TOLERANCE, err_msg=name)
                np.testing.assert_allclose(J[i], J_kdl, rtol=0, atol=FK_TOLERANCE, err_msg=name)

    def test_single_configuration_equals_its_batch_row_for_any_thread_count(self):
        d = armstudy.load_design(design_path("final_prototype_9dof"))
        q = random_configurations(d, 64, seed=2)
        one = d.jacobian(q, threads=1)
        two = d.jacobian(q, threads=2)
        np.testing.assert_array_equal(one, two)
        np.testing.assert_array_equal(d.jacobian(q[5]), one[5])
        np.testing.assert_array_equal(d.fk(q[7]), d.fk(q, threads=2)[7])

    def test_joint_frames_equal_kdl_segment_frames(self):
        d = armstudy.load_design(design_path("final_prototype_7dof"))
        chain = kdl_chain(d)
        q = random_configurations(d, 20, seed=3)
        F = d.frames(q)
        solver = kdl.ChainFkSolverPos_recursive(chain)
        for i in range(len(q)):
            qa = kdl.JntArray(d.dof)
            for k in range(d.dof):
                qa[k] = q[i][k]
            for j in range(d.dof):
                f = kdl.Frame()
                solver.JntToCart(qa, f, 2 * j + 2)  # the fixed offset and the joint of joint j
                np.testing.assert_allclose(F[i, j, :3, 3], [f.p[0], f.p[1], f.p[2]], atol=FK_TOLERANCE)
                np.testing.assert_allclose(
                    F[i, j, :3, :3], [[f.M[r, c] for c in range(3)] for r in range(3)], atol=FK_TOLERANCE)


class KinematicsAgainstCli(unittest.TestCase):
    def test_fk_equals_armstudy_fk_json(self):
        for name in DESIGNS:
            d = armstudy.load_design(design_path(name))
            for q in random_configurations(d, 3, seed=4):
                _, out, _ = cli("fk", design_path(name), "--json", "--q=" + ",".join(repr(v) for v in q))
                tcp = json.loads(out)["frames"][-1]
                T = d.fk(q)
                self.assertEqual(tcp["frame"], "tcp")
                np.testing.assert_array_equal(T[:3, 3], [tcp["x_m"], tcp["y_m"], tcp["z_m"]])
                R_cli = rot_xyz(tcp["alpha"], tcp["beta"], tcp["gamma"])
                np.testing.assert_allclose(T[:3, :3], R_cli, rtol=0, atol=FK_TOLERANCE)


class TaskJacobian(unittest.TestCase):
    def test_spraying_rows_and_manipulability_from_the_geometric_jacobian(self):
        d = armstudy.load_design(design_path("final_prototype_7dof"))
        chain = kdl_chain(d)
        q = random_configurations(d, 50, seed=5)
        Jt = d.task_jacobian(q, "spraying")
        w = d.manipulability(q, "spraying")
        self.assertEqual(Jt.shape, (50, 5, d.dof))
        for i in range(len(q)):
            T, J = kdl_fk_and_jacobian(chain, q[i])
            a = T[:3, :3] @ d.tool_axis
            # Two rows of the angular Jacobian perpendicular to the tool axis: any orthonormal
            # basis of that plane gives the same determinant.
            b1 = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
            b1 /= np.linalg.norm(b1)
            b2 = np.cross(a, b1)
            rows = np.vstack([J[:3], b1 @ J[3:], b2 @ J[3:]])
            expected = np.sqrt(np.linalg.det(rows @ rows.T))
            self.assertLess(abs(w[i] - expected), MANIP_TOLERANCE * max(1.0, expected))
            np.testing.assert_allclose(Jt[i, :3], J[:3], atol=FK_TOLERANCE)
            self.assertLess(abs(np.sqrt(np.linalg.det(Jt[i] @ Jt[i].T)) - w[i]), MANIP_TOLERANCE)

    def test_full_and_position_rows_are_the_geometric_rows(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))
        q = random_configurations(d, 10, seed=6)
        J = d.jacobian(q)
        np.testing.assert_array_equal(d.task_jacobian(q, "full"), J)
        np.testing.assert_array_equal(d.task_jacobian(q, "position"), J[:, :3])
        m = d.manipulability(q, "position")
        np.testing.assert_allclose(m, np.sqrt(np.linalg.det(J[:, :3] @ J[:, :3].transpose(0, 2, 1))),
                                   rtol=MANIP_TOLERANCE)


if __name__ == "__main__":
    unittest.main()
