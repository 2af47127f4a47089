"""Hostile arguments and study dicts: the module applies the CLI's bounds (threads, unit size,
residual-map bins, nesting, finite and plausible table entries, design names) and raises
armstudy.InputError naming the argument or the dict's key path. Calls that crashed the interpreter
or ran away with memory run in a child process (support.run_isolated), so a crash fails the test
instead of ending the runner."""
import math
import os
import tempfile
import unittest

import numpy as np

import armstudy
from support import design_path, run_isolated

# A one-pose reach study (fast when it runs at all).
TINY_STUDY = f"""
def tiny_study():
    return {{"study": {{"name": "tiny"}},
            "design": [{{"file": {design_path("first_prototype_6dof")!r}}}],
            "reach": {{"task_space": "spraying", "grid": [{{
                "name": "one", "x": "0.2 m", "y": "0.8 m", "z": "1.2 m",
                "alpha": "0 deg", "gamma": "0 deg"}}]}}}}
"""
DRIVE_DESIGN = design_path("final_prototype_9dof")
DRIVE_DATA = os.path.join(os.path.dirname(DRIVE_DESIGN), "..", "studies", "data",
                          "drive_testbed_module_b2.csv")
# Address space of a child that calls compare/fit: far above what the bounded calls need, far below
# the 1.6 GB of 10^8 speed bins (a runaway allocation fails there instead of swapping).
CHILD_MEMORY_BYTES = 3 << 30


class Threads(unittest.TestCase):
    def test_run_study_threads_and_unit_size_within_the_cli_bounds(self):
        with tempfile.TemporaryDirectory() as out:
            results = run_isolated(TINY_STUDY + f"""
calls = [dict(threads=100000), dict(threads=257), dict(threads=-1), dict(unit_size=10**9 + 1),
         dict(unit_size=-1)]
print(json.dumps([outcome(lambda c=c: armstudy.run_study(tiny_study(), output={out!r}, **c))
                  for c in calls]))
""")
            self.assertFalse(os.listdir(out), "nothing is written for a bad argument")
        for r, key in zip(results, ["threads", "threads", "threads", "unit_size", "unit_size"]):
            self.assertEqual(r["raised"], "InputError", r)
            self.assertEqual(r["key"], key, r)
        self.assertIn("0..256", results[0]["message"])

    def test_kernel_threads_raise_input_error(self):
        d = armstudy.load_design(design_path("first_prototype_6dof"))
        for threads in (100000, 257, -1):
            with self.assertRaises(armstudy.InputError) as e:
                d.fk(np.zeros(6), threads=threads)
            self.assertEqual(e.exception.key, "threads")
            with self.assertRaises(armstudy.InputError):
                d.solve_batch(np.zeros((2, 6)), threads=threads)


class Nesting(unittest.TestCase):
    def test_self_reference_and_deep_nesting_raise_input_error(self):
        results = run_isolated(TINY_STUDY + """
def self_reference():
    s = tiny_study()
    s["reach"]["grid"][0]["x"] = s
    return s

def deep(kind, depth):
    s = tiny_study()
    v = "0.2 m"
    for _ in range(depth):
        v = [v] if kind == "list" else {"x": v}
    s["reach"]["grid"][0]["x"] = v
    return s

def repeated(levels):
    s = tiny_study()
    v = "0.2 m"
    for _ in range(levels):
        v = [v, v]  # one list twice: 2^levels values once expanded
    s["reach"]["grid"][0]["x"] = v
    return s

studies = [self_reference(), deep("list", 100000), deep("dict", 100000), deep("list", 257),
           deep("list", 250), deep("dict", 250), repeated(40)]
print(json.dumps([outcome(lambda s=s: armstudy.check_study(s)) for s in studies]))
""", timeout=120)
        self.assertEqual(results[6]["raised"], "InputError", results[6])
        self.assertIn("more than 1000000 values", results[6]["message"])
        results = results[:6]
        for r in results[:4]:
            self.assertEqual(r["raised"], "InputError", r)
            self.assertTrue(r["key"].startswith("reach.grid[0].x"), r)
            self.assertIn("nested deeper than 256", r["message"])
        # Below the cap: the study reader's own error about the value, not the nesting.
        for r in results[4:]:
            self.assertEqual(r["raised"], "InputError", r)
            self.assertNotIn("nested deeper", r["message"])


class Bins(unittest.TestCase):
    def test_residual_map_bins_within_the_cli_bounds(self):
        results = run_isolated(f"""
nine = armstudy.load_design({DRIVE_DESIGN!r})
d = armstudy.load_design({design_path("first_prototype_6dof")!r})
s = armstudy.synthesize_tcp(d, rows=40, seed=3)
drive = dict(kind="drive", joint="j6")
calls = [
    lambda: armstudy.compare(nine, {DRIVE_DATA!r}, speed_bins=10**8, **drive),
    lambda: armstudy.compare(nine, {DRIVE_DATA!r}, load_bins=0, **drive),
    lambda: armstudy.fit(nine, {DRIVE_DATA!r}, speed_bins=1001, **drive),
    lambda: armstudy.compare(d, s["q"], pose=s["pose"], variable_bins=10**8),
    lambda: armstudy.fit(d, s["q"], pose=s["pose"], workspace_bins=1001),
]
print(json.dumps([outcome(c) for c in calls]))
""", memory_bytes=CHILD_MEMORY_BYTES)
        keys = ["speed_bins", "load_bins", "speed_bins", "variable_bins", "workspace_bins"]
        for r, key in zip(results, keys):
            self.assertEqual(r["raised"], "InputError", r)
            self.assertEqual(r["key"], key, r)
            self.assertIn("1..1000", r["message"])


class Entries(unittest.TestCase):
    def setUp(self):
        self.d = armstudy.load_design(design_path("first_prototype_6dof"))

    def test_entries_finite_and_plausible(self):
        for key, value in [("joint.j2.z", math.nan), ("joint.j2.z", math.inf), ("joint.j2.z", 1e300),
                           ("tcp.z", -1e300), ("joint.j3.max", 1e300), ("base.alpha", -math.inf),
                           ("joint.j1.max_velocity", 1e300), ("payload.mass", 1e300)]:
            with self.assertRaises(armstudy.InputError, msg=f"{key} = {value}") as e:
                self.d.with_entries({key: value})
            self.assertEqual(e.exception.key, key)
        v = self.d.with_entries({"joint.j2.z": -0.2, "tcp.z": 0.1})
        self.assertEqual(v.joints[1]["z"], -0.2)

    def test_names_checked_as_design_names(self):
        for name in ["../../evil", "a/b", "x y", "semi;colon", "quote\"", "new\nline"]:
            with self.assertRaises(armstudy.InputError, msg=name) as e:
                self.d.with_entries({"joint.j2.z": -0.2}, name=name)
            self.assertEqual(e.exception.key, "name")
            self.assertIn("letters, digits", e.exception.message)
        self.assertEqual(self.d.with_entries({}, name="ok_name-1.0").name, "ok_name-1.0")


class DictValues(unittest.TestCase):
    def check(self, study, key, *message_parts):
        with self.assertRaises(armstudy.InputError) as e:
            armstudy.check_study(study)
        self.assertEqual(e.exception.file, "study dict")
        self.assertEqual(e.exception.key, key)
        for part in message_parts:
            self.assertIn(part, e.exception.message)
        return e.exception

    def test_values_without_a_toml_form_name_their_key_path(self):
        ns = {}
        exec(TINY_STUDY, ns)
        tiny = ns["tiny_study"]
        s = tiny()
        s["reach"]["grid"][0]["x"] = None
        self.check(s, "reach.grid[0].x", "None")
        s = tiny()
        s["reach"]["grid"][0]["gamma"] = ["0 deg", None]
        self.check(s, "reach.grid[0].gamma[1]", "None")
        for big in (2**64, -2**63 - 1, 10**400):
            s = tiny()
            s["reach"]["grid"][0]["x"] = {"from": big, "to": 1, "step": 0.1}
            self.check(s, "reach.grid[0].x.from", "64-bit")
        s = tiny()
        s["reach"]["grid"][0]["y"] = object()
        self.check(s, "reach.grid[0].y", "object")
        s = tiny()
        # A numpy array is its list (tolist()): three bare numbers, whose third the reader refuses.
        s["reach"]["grid"][0]["y"] = np.zeros(3)
        self.check(s, "reach.grid[0].y[2]")
        s = tiny()
        s["reach"]["grid"][0]["y"] = np.array([object()], dtype=object)
        self.check(s, "reach.grid[0].y[0]", "object")
        s = tiny()
        s["reach"][5] = "x"
        self.check(s, "reach", "key 5")
        s = tiny()
        s["reach"]["grid"][0]["x"] = math.nan  # TOML holds it; the study reader refuses it
        self.check(s, "reach.grid[0].x", "not finite")
        for study in (None, 5, ["a"]):
            with self.assertRaises(armstudy.InputError):
                armstudy.check_study(study)
            with self.assertRaises(armstudy.InputError):
                armstudy.run_study(study)

    def test_numpy_scalars_are_numbers(self):
        ns = {}
        exec(TINY_STUDY, ns)
        s = ns["tiny_study"]()
        s["reach"]["grid"][0]["x"] = np.float64(0.2)
        s["reach"]["starts"] = np.int64(4)
        self.assertEqual(armstudy.check_study(s)["study"], "tiny")


if __name__ == "__main__":
    unittest.main()
