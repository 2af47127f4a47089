"""Poses both ways: the study's Cardan parameters, 4x4 transforms, position + rotation matrix or
quaternion and the spray direction d(alpha, gamma) convert into each other (round trips to 1e-12,
each form against its closed form written here), and solve takes an SE(3) transform or a tool-axis
target, solving exactly as the equivalent study pose."""
import unittest

import numpy as np

import armstudy
from support import design_path, rot_xyz

TOL = 1e-12


def random_poses(n, seed, beta_max=1.4):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-2, 2, (n, 3)), rng.uniform(-np.pi, np.pi, n),
                            rng.uniform(-beta_max, beta_max, n), rng.uniform(-np.pi, np.pi, n)])


def random_quaternions(n, seed):
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1)[:, None]


def quaternion_matrix(q):
    """The rotation of a unit quaternion (w, x, y, z), written out."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


class Conversions(unittest.TestCase):
    def test_pose_to_matrix_is_rx_ry_rz(self):
        poses = random_poses(200, 1)
        T = armstudy.pose_to_matrix(poses)
        self.assertEqual(T.shape, (200, 4, 4))
        for w, t in zip(poses, T):
            np.testing.assert_allclose(t[:3, :3], rot_xyz(*w[3:]), atol=1e-15)
            np.testing.assert_array_equal(t[:3, 3], w[:3])
            np.testing.assert_array_equal(t[3], [0, 0, 0, 1])
        np.testing.assert_array_equal(armstudy.pose_to_matrix(poses[0]), T[0])

    def test_pose_matrix_pose_round_trip(self):
        poses = random_poses(2000, 2)
        back = armstudy.matrix_to_pose(armstudy.pose_to_matrix(poses))
        np.testing.assert_allclose(back, poses, rtol=0, atol=TOL)

    def test_matrix_pose_matrix_round_trip(self):
        # Any rotation, the Cardan singularity (beta = +-90 deg) and its neighbourhood included.
        R = np.array([quaternion_matrix(q) for q in random_quaternions(2000, 3)])
        near = np.array([rot_xyz(a, s * (np.pi / 2 - e), g) for a, g, e, s in
                         zip(np.linspace(-3, 3, 50), np.linspace(3, -3, 50), np.logspace(-14, -2, 50),
                             np.tile([1, -1], 25))])
        T = armstudy.make_transform(np.zeros((2050, 3)), rotation=np.concatenate([R, near]))
        back = armstudy.pose_to_matrix(armstudy.matrix_to_pose(T))
        np.testing.assert_allclose(back[:2000], T[:2000], rtol=0, atol=TOL)
        # Within 1e-2 rad of the singularity the angles come from nearly parallel axes: 1e-11.
        np.testing.assert_allclose(back[2000:], T[2000:], rtol=0, atol=1e-11)
        self.assertLessEqual(np.abs(armstudy.matrix_to_pose(T)[:, 4]).max(), np.pi / 2)

    def test_quaternions_both_ways(self):
        q = random_quaternions(1000, 4)
        p = np.random.default_rng(5).uniform(-1, 1, (1000, 3))
        T = armstudy.make_transform(p, quaternion=q)
        for qi, t in zip(q, T):
            np.testing.assert_allclose(t[:3, :3], quaternion_matrix(qi), atol=1e-15)
        back = armstudy.matrix_to_quaternion(T)
        same_sign = np.where(q[:, :1] < 0, -q, q)
        np.testing.assert_allclose(back, same_sign, rtol=0, atol=TOL)
        np.testing.assert_allclose(armstudy.matrix_to_quaternion(T[:, :3, :3]), back, rtol=0, atol=0)
        # Position + rotation matrix and the identity rotation.
        np.testing.assert_array_equal(armstudy.make_transform(p[0], rotation=T[0, :3, :3]), T[0])
        np.testing.assert_array_equal(armstudy.make_transform([1, 2, 3])[:3, :3], np.eye(3))

    def test_spray_direction_both_ways(self):
        rng = np.random.default_rng(6)
        alpha, gamma = rng.uniform(-np.pi, np.pi, 2000), rng.uniform(-1.57, 1.57, 2000)
        d = armstudy.spray_direction(alpha, gamma)
        closed = np.column_stack([-np.sin(gamma), np.cos(alpha) * np.cos(gamma),
                                  np.sin(alpha) * np.cos(gamma)])
        np.testing.assert_allclose(d, closed, rtol=0, atol=1e-15)
        # d = Rx(alpha) Rz(gamma) e_y: the y column of the pose (0, 0, 0, alpha, 0, gamma).
        cols = armstudy.pose_to_matrix(np.column_stack([np.zeros((2000, 3)), alpha, np.zeros(2000), gamma]))
        np.testing.assert_allclose(d, cols[:, :3, 1], rtol=0, atol=1e-15)
        angles = armstudy.direction_to_angles(d)
        np.testing.assert_allclose(angles, np.column_stack([alpha, gamma]), rtol=0, atol=TOL)
        np.testing.assert_allclose(armstudy.direction_to_angles(3 * d[0]), angles[0], atol=TOL)
        np.testing.assert_allclose(armstudy.spray_direction(0.0, np.radians(40)),
                                   [-0.6427876096865393, 0.766044443118978, 0.0], atol=1e-15)

    def test_bad_shapes_and_non_rotations(self):
        with self.assertRaises(ValueError):
            armstudy.pose_to_matrix(np.zeros(5))
        with self.assertRaises(ValueError):
            armstudy.matrix_to_pose(np.diag([1.0, 2.0, 1.0, 1.0]))
        with self.assertRaises(ValueError):
            armstudy.make_transform([0, 0, 0], rotation=np.eye(3), quaternion=[1, 0, 0, 0])


class Targets(unittest.TestCase):
    def test_se3_target_solves_as_its_full_pose(self):
        d = armstudy.load_design(design_path("final_prototype_9dof"))
        rng = np.random.default_rng(7)
        q = d.lower + rng.uniform(0.3, 0.7, (20, d.dof)) * (d.upper - d.lower)
        T = d.fk(q)
        reached = 0
        for i, t in enumerate(T):
            r = d.solve(t, pose_id=i)
            # The same pose through its Cardan parameters: the rotation comes back to rounding only,
            # so the solution agrees to rounding, not bit for bit (the transform is used as it is).
            same = d.solve(armstudy.matrix_to_pose(t), "full", pose_id=i)
            self.assertEqual(r["reachable"], same["reachable"])
            np.testing.assert_allclose(r["q"], same["q"], rtol=0, atol=1e-9)
            if r["reachable"]:
                reached += 1
                got = d.fk(r["q"])
                self.assertLessEqual(np.linalg.norm(got[:3, 3] - t[:3, 3]), 1e-3)
                angle = np.arccos(np.clip((np.trace(got[:3, :3].T @ t[:3, :3]) - 1) / 2, -1, 1))
                self.assertLessEqual(angle, np.radians(0.5) + 1e-12)
        self.assertGreaterEqual(reached, 15)      # poses of configurations: nearly all reachable
        b = d.solve_batch(T, pose_ids=np.arange(20))
        self.assertEqual(int(b["reachable"].sum()), reached)

    def test_axis_target_is_the_spraying_pose(self):
        d = armstudy.load_design(design_path("final_prototype_7dof"))
        rng = np.random.default_rng(8)
        poses = np.column_stack([rng.uniform(-0.6, 0.6, 30), rng.uniform(0.4, 1.0, 30), np.full(30, 1.2),
                                 rng.uniform(-0.3, 0.3, 30), np.zeros(30), rng.uniform(-0.7, 0.7, 30)])
        axes = armstudy.spray_direction(poses[:, 3], poses[:, 5])
        batch = d.solve_batch(poses[:, :3], axis=axes)
        spraying = d.solve_batch(poses, "spraying")
        for k in spraying:
            if isinstance(spraying[k], list):
                self.assertEqual(batch[k], spraying[k], k)
            else:
                np.testing.assert_array_equal(batch[k], spraying[k], err_msg=k)
        one = d.solve(poses[3, :3], axis=axes[3], pose_id=3)
        np.testing.assert_array_equal(one["q"], spraying["q"][3])
        ok = spraying["reachable"]
        self.assertGreater(ok.sum(), 10)
        tool = d.fk(batch["q"][ok])[:, :3, :3] @ d.tool_axis
        self.assertGreater(np.einsum("ij,ij->i", tool, axes[ok]).min(), np.cos(np.radians(0.5)) - 1e-12)

    def test_batch_returns_what_solve_returns(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))
        poses = random_poses(5, 9)
        one = d.solve(poses[0])
        batch = d.solve_batch(poses)
        self.assertEqual(set(one), set(batch))
        for k, v in one.items():
            got = batch[k][0]
            if isinstance(v, float) and np.isnan(v):
                self.assertTrue(np.isnan(got), k)
            elif isinstance(v, np.ndarray):
                np.testing.assert_array_equal(got, v, err_msg=k)
            else:
                self.assertEqual(got, v, k)


if __name__ == "__main__":
    unittest.main()
