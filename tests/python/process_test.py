"""The module in worker processes: a fork-based multiprocessing.Pool evaluates designs after the
parent ran a batch on several OpenMP threads (the OpenMP runtime is not fork-safe: the child runs
its calls on one thread), and designs and study results pickle, so they travel to workers and
back. Each pool runs in a child python under a timeout, so a hang fails the test."""
import os
import pickle
import signal
import subprocess
import sys
import tempfile
import textwrap
import unittest

import numpy as np

import armstudy
from support import design_path

POOL = """
import multiprocessing, sys
import numpy as np
import armstudy

def manipulability(path):
    d = armstudy.load_design(path)
    q = d.lower + np.linspace(0.2, 0.8, 400)[:, None] * (d.upper - d.lower)
    return float(d.manipulability(q, task="full").sum()), float(d.fk(q)[:, 2, 3].sum())

paths = sys.argv[1:]
d = armstudy.load_design(paths[0])
q = d.lower + np.random.default_rng(1).random((20000, d.dof)) * (d.upper - d.lower)
d.fk(q, threads=4)                      # the OpenMP thread pool exists in the parent now
d.manipulability(q, task="full", threads=4)
serial = [manipulability(p) for p in paths]
with multiprocessing.get_context("fork").Pool(4) as pool:
    pooled = pool.map(manipulability, paths * 2)
assert pooled == serial * 2, (pooled, serial)
print("ok", len(pooled))
"""


def run_child(code, *args, timeout=60):
    """Runs code in a child python in its own process group; on timeout the whole group (the pool's
    workers too) is killed and TimeoutExpired raised."""
    p = subprocess.Popen([sys.executable, "-c", code, *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        raise
    return subprocess.CompletedProcess(p.args, p.returncode, out, err)


class ForkedPool(unittest.TestCase):
    def test_fork_pool_after_a_threaded_batch(self):
        paths = [design_path(n) for n in ("first_prototype_6dof", "final_prototype_9dof")]
        try:
            p = run_child(POOL, *paths, timeout=30)
        except subprocess.TimeoutExpired:
            self.fail("the forked pool hung after a multithreaded batch in the parent")
        self.assertEqual(p.returncode, 0, p.stderr[-2000:])
        self.assertIn("ok 4", p.stdout)

    def test_pool_of_studies(self):
        # The documented way to run many studies in a process pool (docs/python.md).
        code = textwrap.dedent("""
            import multiprocessing, sys
            import numpy as np
            import armstudy
            def run(args):
                name, z = args
                study = {"study": {"name": name},
                         "design": [{"file": sys.argv[1]}],
                         "reach": {"task_space": "full", "grid": [{"name": "g",
                                   "x": {"from": "-0.2 m", "to": "0.2 m", "step": "0.1 m"},
                                   "y": "0.6 m", "z": z, "alpha": "0 deg", "beta": "0 deg",
                                   "gamma": "0 deg"}]}}
                return armstudy.run_study(study, output=sys.argv[2], threads=1)
            d = armstudy.load_design(sys.argv[1])
            d.fk(np.zeros((5000, d.dof)), threads=4)
            with multiprocessing.get_context("fork").Pool(2) as pool:
                results = pool.map(run, [("a", "0.8 m"), ("b", "1.0 m")])
            print("ok", [r["study"] for r in results], sorted(results[0]["maps"]))
        """)
        with tempfile.TemporaryDirectory() as out:
            try:
                p = run_child(code, design_path("first_prototype_6dof"), out, timeout=120)
            except subprocess.TimeoutExpired:
                self.fail("the pool of studies hung")
            self.assertEqual(p.returncode, 0, p.stderr[-2000:])
            self.assertIn("ok ['a', 'b']", p.stdout)
            self.assertTrue(os.path.isfile(os.path.join(out, "b", "manifest.json")))


class Pickle(unittest.TestCase):
    def test_design_round_trip(self):
        for name in ("first_prototype_6dof", "final_prototype_9dof"):
            d = armstudy.load_design(design_path(name))
            e = pickle.loads(pickle.dumps(d))
            self.assertIsInstance(e, armstudy.Design)
            self.assertEqual((e.name, e.dof, e.file, e.file_hash), (d.name, d.dof, d.file, d.file_hash))
            self.assertEqual(e.to_toml(), d.to_toml())
            q = d.lower + np.random.default_rng(3).random((50, d.dof)) * (d.upper - d.lower)
            np.testing.assert_array_equal(e.fk(q), d.fk(q))
            np.testing.assert_array_equal(e.jacobian(q), d.jacobian(q))

    def test_variant_round_trip(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))
        v = d.with_entries({"tcp.z": 0.31}, name="longer_tool")
        e = pickle.loads(pickle.dumps(v))
        self.assertEqual((e.name, e.tcp), (v.name, v.tcp))
        q = np.zeros(d.dof)
        np.testing.assert_array_equal(e.fk(q), v.fk(q))

    def test_urdf_design_round_trip(self):
        robots = os.environ.get("ARMSTUDY_ROBOTS_DIR", "")
        urdf = os.path.join(robots, "ur_description", "urdf", "ur5_robot.urdf")
        if not os.path.isfile(urdf):
            self.skipTest("no UR5 URDF under ARMSTUDY_ROBOTS_DIR")
        d = armstudy.load_design(urdf, collision=False)
        e = pickle.loads(pickle.dumps(d))
        self.assertEqual(e.to_urdf(), d.to_urdf())
        self.assertEqual(e.warnings, d.warnings)
        q = np.linspace(-1, 1, d.dof)
        np.testing.assert_array_equal(e.fk(q), d.fk(q))

    def test_study_result_round_trip(self):
        study = {"study": {"name": "pickled"}, "design": [{"file": design_path("first_prototype_6dof")}],
                 "reach": {"task_space": "full", "grid": [{"name": "g", "x": {"from": "-0.1 m", "to": "0.1 m",
                           "step": "0.1 m"}, "y": "0.6 m", "z": "1.0 m", "alpha": "0 deg", "beta": "0 deg",
                           "gamma": "0 deg"}]}}
        with tempfile.TemporaryDirectory() as out:
            r = armstudy.run_study(study, output=out, threads=1)
            s = pickle.loads(pickle.dumps(r))
            self.assertEqual(type(s), type(r))
            self.assertEqual(s["study"], "pickled")
            self.assertEqual(sorted(s["maps"]), sorted(r["maps"]))
            for f, m in r["maps"].items():
                for a, v in m["arrays"].items():
                    np.testing.assert_array_equal(s["maps"][f]["arrays"][a], v)


if __name__ == "__main__":
    unittest.main()
