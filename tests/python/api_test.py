"""The typed stub beside the module names exactly the module's functions and Design's members, and
every one of them has a docstring; batch calls release the GIL (another Python thread runs
while a batch solves)."""
import ast
import os
import threading
import unittest

import numpy as np

import armstudy
from support import design_path


def stub_names():
    path = os.path.join(os.path.dirname(armstudy.__file__), "armstudy.pyi")
    tree = ast.parse(open(path).read())
    functions = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    design = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Design")
    members = {n.name for n in design.body if isinstance(n, ast.FunctionDef)}
    return functions, members


class Api(unittest.TestCase):
    def test_stub_matches_the_module(self):
        functions, members = stub_names()
        module = {n for n in dir(armstudy) if callable(getattr(armstudy, n)) and not n.startswith("_")
                  and n[0].islower()}
        self.assertEqual(functions, module)
        design = {n for n in dir(armstudy.Design) if not n.startswith("_")}
        self.assertEqual(members, design)
        for n in module:
            self.assertTrue(getattr(armstudy, n).__doc__, n)

    def test_batches_release_the_gil(self):
        d = armstudy.load_design(design_path("final_prototype_9dof"))
        rng = np.random.default_rng(31)
        poses = np.column_stack([rng.uniform(-0.6, 0.6, 4000), rng.uniform(0.4, 1.0, 4000),
                                 np.full(4000, 1.0), np.zeros(4000), np.zeros(4000), np.zeros(4000)])
        started = threading.Event()
        done = threading.Event()

        def batch():
            started.set()
            d.solve_batch(poses, threads=1)
            done.set()

        t = threading.Thread(target=batch)
        t.start()
        started.wait()
        ticks = 0
        while not done.is_set():
            ticks += 1
        t.join()
        # With the GIL held through the batch this loop would get at most a few switch intervals.
        self.assertGreater(ticks, 10000)


if __name__ == "__main__":
    unittest.main()
