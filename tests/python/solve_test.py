"""A batch solve of 10,000 poses agrees with the single-pose solver called with the same starts
(the same pose ids and warm starts), on any thread count; a solved configuration reaches its pose
by the module's FK."""
import unittest

import numpy as np

import armstudy
from support import design_path, rot_xyz

POSES = 10000
POSITION_TOLERANCE_M = 1e-3      # the solver's default tolerance (defaults.hpp)


def spraying_row_poses(count, seed):
    """Poses on the thesis Fig. 3.8 row: x, y on the wall at z = 1.2 m, alpha = 0, gamma = +-40 deg."""
    rng = np.random.default_rng(seed)
    p = np.zeros((count, 6))
    p[:, 0] = rng.uniform(-0.78, 0.78, count)
    p[:, 1] = rng.uniform(0.3, 1.2, count)
    p[:, 2] = 1.2
    p[:, 5] = np.where(rng.random(count) < 0.5, -1.0, 1.0) * np.radians(40)
    return p


class Solve(unittest.TestCase):
    def test_batch_equals_single_pose_solves(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))
        poses = spraying_row_poses(POSES, seed=11)
        ids = np.arange(POSES, dtype=np.uint64) * 7 + 3
        batch = d.solve_batch(poses, "spraying", pose_ids=ids, threads=2)
        self.assertEqual(batch["q"].shape, (POSES, d.dof))
        for i in range(POSES):
            one = d.solve(poses[i], "spraying", pose_id=int(ids[i]))
            self.assertEqual(one["status"], batch["status"][i])
            np.testing.assert_array_equal(one["q"], batch["q"][i])
            self.assertEqual(one["manipulability"], batch["manipulability"][i])
            self.assertEqual(one["status_name"], armstudy.STATUS_NAMES[batch["status"][i]])
        reachable = batch["status"] == 0
        self.assertGreater(reachable.sum(), POSES // 4)   # the row is mostly reachable
        self.assertGreater((~reachable).sum(), 0)         # and its corners are not
        # A reachable solution puts the TCP on its pose and the tool axis along the spray direction.
        T = d.fk(batch["q"][reachable])
        err = np.linalg.norm(T[:, :3, 3] - poses[reachable, :3], axis=1)
        self.assertLessEqual(err.max(), POSITION_TOLERANCE_M)
        np.testing.assert_array_equal(d.manipulability(batch["q"][reachable], "spraying"),
                                      batch["manipulability"][reachable])

    def test_thread_count_and_warm_starts(self):
        d = armstudy.load_design(design_path("final_prototype_7dof"))
        poses = spraying_row_poses(300, seed=12)
        one = d.solve_batch(poses, "spraying", threads=1)
        two = d.solve_batch(poses, "spraying", threads=2)
        for k in one:
            if isinstance(one[k], list):
                self.assertEqual(one[k], two[k], k)
            else:
                np.testing.assert_array_equal(one[k], two[k], err_msg=k)
        warm = np.tile((d.lower + d.upper) / 2, (len(poses), 1))
        wb = d.solve_batch(poses, "spraying", warm_starts=warm, threads=2)
        for i in range(0, len(poses), 37):
            s = d.solve(poses[i], "spraying", pose_id=i, warm_start=warm[i])
            np.testing.assert_array_equal(s["q"], wb["q"][i])

    def test_collision_aware_solutions_are_clear_of_self_collision(self):
        d = armstudy.load_design(design_path("final_prototype_9dof"))
        poses = spraying_row_poses(400, seed=13)
        poses[:, 2] = 0.5
        aware = d.solve_batch(poses, "spraying", threads=2, self_collision=True)
        plain = d.solve_batch(poses, "spraying", threads=2)   # default: no check
        ok = aware["status"] == 0
        self.assertGreater(ok.sum(), 100)
        distances = d.self_distances(aware["q"][ok]).min(axis=1)
        self.assertTrue((distances > 0).all())
        np.testing.assert_array_equal(distances, aware["min_distance"][ok])
        self.assertTrue(np.isnan(plain["min_distance"]).all())
        # Without the check some solutions collide, and each of those poses is either cleared by the
        # collision-aware solve or reported as reachable only in self-collision.
        colliding = (plain["status"] == 0) & (d.self_distances(plain["q"]).min(axis=1) <= 0)
        self.assertGreater(colliding.sum(), 10)
        self.assertTrue(np.isin(aware["status"][colliding], [0, 4]).all())
        self.assertGreater((aware["status"] == 4).sum(), 0)
        one = d.solve(poses[7], "spraying", pose_id=7, self_collision=True)
        self.assertEqual(one["status"], aware["status"][7])
        np.testing.assert_array_equal(one["q"], aware["q"][7])

    def test_full_pose_of_a_configuration_is_reachable(self):
        d = armstudy.load_design(design_path("final_prototype_9dof"))
        q = (d.lower + d.upper) / 2 + 0.1
        T = d.fk(q)
        b = np.arcsin(np.clip(T[0, 2], -1, 1))
        a = np.arctan2(-T[1, 2], T[2, 2])
        g = np.arctan2(-T[0, 1], T[0, 0])
        np.testing.assert_allclose(rot_xyz(a, b, g), T[:3, :3], atol=1e-12)
        r = d.solve([*T[:3, 3], a, b, g], "full")
        self.assertTrue(r["reachable"], r["status_name"])
        np.testing.assert_allclose(d.fk(r["q"])[:3, 3], T[:3, 3], atol=POSITION_TOLERANCE_M)


if __name__ == "__main__":
    unittest.main()
