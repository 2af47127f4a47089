"""Progressive stem maps from Python: run_study(preview=K, on_preview=f) calls f with each design's
preview once it is on disk and before that design's map exists, writes the same other files as a
run without the preview, and an exception raised by f stops the run (no manifest) and reaches the
caller; bad arguments are InputErrors naming them."""
import filecmp
import os
import tempfile
import unittest

import armstudy
from support import design_path

DESIGNS = ["first_prototype_9dof", "final_prototype_7dof"]
STUDY = {"study": {"name": "py_preview"},
         "design": [{"file": design_path(d)} for d in DESIGNS],
         "dexterity": {"stem_x": "0.225 m", "stem_y": "0.7 m", "radius": "0.15 m",
                       "gamma": {"min": "-30 deg", "max": "30 deg", "step": "5 deg"},
                       "z": {"min": "0.6 m", "max": "0.9 m", "step": "0.05 m"},
                       "task": "position_axis", "audit": {"cells": 4, "starts": 20}}}


def files_under(root):
    out = set()
    for d, _, names in os.walk(root):
        out.update(os.path.relpath(os.path.join(d, n), root) for n in names)
    return out


class Stop(Exception):
    pass


class Preview(unittest.TestCase):
    def test_previews_are_announced_before_their_maps_and_change_no_other_file(self):
        with tempfile.TemporaryDirectory() as tmp:
            plain = armstudy.run_study(STUDY, output=os.path.join(tmp, "plain"), threads=2)
            out = os.path.join(tmp, "progressive")
            seen = []

            def announced(path):
                design = os.path.splitext(os.path.basename(path))[0]
                vti = os.path.join(out, "py_preview", "dexterity", design + ".vti")
                seen.append((os.path.relpath(path, os.path.join(out, "py_preview")),
                             os.path.isfile(path), os.path.exists(vti)))

            run = armstudy.run_study(STUDY, output=out, threads=2, preview=3,
                                     on_preview=announced)
            previews = sorted(f"dexterity/preview/{d}.png" for d in DESIGNS)
            self.assertEqual(sorted(s[0] for s in seen), previews)
            for name, there, map_there in seen:
                self.assertTrue(there, name)
                self.assertFalse(map_there, name)
            a, b = files_under(plain["output_dir"]), files_under(run["output_dir"])
            extra = sorted(b - a)
            self.assertEqual(extra, sorted(previews + [p[:-4] + ".svg" for p in previews]))
            self.assertEqual(a - b, set())
            for f in sorted(a - {"manifest.json"}):
                self.assertTrue(filecmp.cmp(os.path.join(plain["output_dir"], f),
                                            os.path.join(run["output_dir"], f), shallow=False), f)
            self.assertTrue(set(previews) <= set(run["files"]))

    def test_an_exception_in_on_preview_stops_the_run_and_is_raised(self):
        with tempfile.TemporaryDirectory() as tmp:
            calls = []

            def fail(path):
                calls.append(path)
                raise Stop(path)

            with self.assertRaises(Stop):
                armstudy.run_study(STUDY, output=tmp, threads=2, preview=3, on_preview=fail)
            self.assertGreaterEqual(len(calls), 1)
            folder = os.path.join(tmp, "py_preview")
            self.assertTrue(os.path.isfile(calls[0]))
            self.assertFalse(os.path.exists(os.path.join(folder, "manifest.json")))

    def test_bad_preview_arguments_name_the_argument(self):
        with tempfile.TemporaryDirectory() as tmp:
            for kwargs, key in (({"preview": 101}, "preview"), ({"preview": -1}, "preview"),
                                ({"preview": 2, "on_preview": "show"}, "on_preview")):
                with self.assertRaises(armstudy.InputError) as e:
                    armstudy.run_study(STUDY, output=tmp, **kwargs)
                self.assertIn(key, str(e.exception))
            self.assertEqual(os.listdir(tmp), [])


if __name__ == "__main__":
    unittest.main()
