"""Python's own types: os.PathLike wherever a path goes, numpy scalars and arrays in study dicts (the
same study as with Python values, byte for byte), integer map arrays as integers, read_map raising
InputError on a wrong file without printing, and a docstring on every public name."""
import filecmp
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import armstudy
from support import ROBOTS_DIR, SOURCE_DIR, design_path


def small_study(name, z, gammas, starts):
    return {"study": {"name": name},
            "design": [{"file": design_path("first_prototype_6dof")}],
            "reach": {"task_space": "spraying", "grid": [{"name": "row",
                      "x": {"from": "-0.2 m", "to": "0.2 m", "step": "0.1 m"}, "y": "0.7 m",
                      "z": z, "alpha": "0 deg", "gamma": gammas}]}}


class PathLike(unittest.TestCase):
    def test_paths_are_accepted_everywhere(self):
        d = armstudy.load_design(pathlib.Path(design_path("first_prototype_6dof")))
        self.assertEqual(d.name, "first_prototype_6dof")
        ur5 = pathlib.Path(ROBOTS_DIR) / "ur_description" / "urdf" / "ur5_robot.urdf"
        u = armstudy.load_design(ur5, collision=False, packages={"example-robot-data": pathlib.Path(ROBOTS_DIR)})
        self.assertEqual(u.dof, 6)
        study = pathlib.Path(SOURCE_DIR) / "studies" / "spraying_row.toml"
        self.assertEqual(armstudy.check_study(study)["study"], "spraying_row")
        with tempfile.TemporaryDirectory() as out:
            r = armstudy.run_study(small_study("p", "1.0 m", "0 deg", 8), output=pathlib.Path(out),
                                   folder=pathlib.Path(SOURCE_DIR), threads=1)
            vti = pathlib.Path(r["output_dir"]) / next(iter(r["maps"]))
            m = armstudy.read_map(vti)
            self.assertEqual(m["dims"][0], 5)


class NumpyValues(unittest.TestCase):
    def test_numpy_values_in_a_study_dict(self):
        with tempfile.TemporaryDirectory() as out:
            plain = armstudy.run_study(small_study("plain", "1.0 m", ["-20 deg", "20 deg"], 8),
                                       output=out, threads=1)
            study = small_study("numpy", np.str_("1.0 m"), np.array(["-20 deg", "20 deg"]), 8)
            study["design"][0]["file"] = np.str_(study["design"][0]["file"])
            study["reach"]["position_tolerance"] = np.array("1 mm")
            plain_study = small_study("plain2", "1.0 m", ["-20 deg", "20 deg"], 8)
            plain_study["reach"]["position_tolerance"] = "1 mm"
            a = armstudy.run_study(study, output=out, threads=1)
            b = armstudy.run_study(plain_study, output=out, threads=1)
            self.assertEqual(sorted(a["maps"]), sorted(b["maps"]))
            for f in a["files"]:
                if f.endswith((".vti", ".csv")):
                    self.assertTrue(filecmp.cmp(os.path.join(a["output_dir"], f),
                                                os.path.join(b["output_dir"], f), shallow=False), f)
            self.assertEqual(sorted(plain["maps"]), sorted(a["maps"]))


class Maps(unittest.TestCase):
    def test_integer_arrays_stay_integers(self):
        with tempfile.TemporaryDirectory() as out:
            r = armstudy.run_study(small_study("ints", "1.0 m", "0 deg", 8), output=out, threads=1)
            m = next(iter(r["maps"].values()))
            status = [a for a in m["arrays"] if a.startswith("status")]
            self.assertTrue(status)
            for a in status:
                self.assertIn(m["arrays"][a].dtype.kind, "iu", a)
            floats = [a for a in m["arrays"] if a.startswith("manipulability")]
            self.assertTrue(floats, list(m["arrays"]))
            for a in floats:
                self.assertEqual(m["arrays"][a].dtype, np.float64, a)

    def test_read_map_raises_on_a_wrong_file_and_prints_nothing(self):
        code = f"""
import armstudy, json, sys
out = []
for path in [{design_path("first_prototype_6dof")!r}, sys.argv[1], sys.argv[1] + ".missing.vti"]:
    try:
        armstudy.read_map(path)
        out.append("returned")
    except armstudy.InputError as e:
        out.append(e.file == path and "InputError")
print(json.dumps(out))
"""
        with tempfile.TemporaryDirectory() as tmp:
            bad = os.path.join(tmp, "bad.vti")
            with open(bad, "w") as f:
                f.write('<?xml version="1.0"?>\n<VTKFile type="ImageData"><ImageData>truncated')
            p = subprocess.run([sys.executable, "-c", code, bad], capture_output=True, text=True, timeout=60)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(p.stdout.strip(), '["InputError", "InputError", "InputError"]')
        self.assertEqual(p.stderr, "")


class Docstrings(unittest.TestCase):
    def test_every_public_name_has_a_docstring(self):
        missing = []
        for name in dir(armstudy):
            if name.startswith("_") or name.isupper():
                continue
            obj = getattr(armstudy, name)
            if not (getattr(obj, "__doc__", None) or "").strip():
                missing.append(name)
            if isinstance(obj, type):
                for member in vars(obj):
                    if member.startswith("_"):
                        continue
                    attr = vars(obj)[member]
                    if not (getattr(attr, "__doc__", None) or "").strip():
                        missing.append(f"{name}.{member}")
        self.assertEqual(missing, [])
        self.assertGreater(len([n for n in dir(armstudy.Design) if not n.startswith("_")]), 25)


if __name__ == "__main__":
    unittest.main()
