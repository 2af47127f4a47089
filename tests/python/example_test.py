"""The worked example of docs/python.md, studies/compare_designs.py, runs and prints its table
with the study's reachable fractions."""
import os
import re
import subprocess
import sys
import tempfile
import unittest

from support import SOURCE_DIR


class Example(unittest.TestCase):
    def test_compare_designs_script(self):
        with tempfile.TemporaryDirectory() as out:
            p = subprocess.run([sys.executable, os.path.join(SOURCE_DIR, "studies", "compare_designs.py"),
                                "--step", "0.1", "--output", out, "--threads", "2"],
                               capture_output=True, text=True, env=os.environ)
            self.assertEqual(p.returncode, 0, p.stderr)
            rows = re.findall(r"^(first_prototype_6dof|final_prototype_7dof)\s+(\d+)\s+([\d.]+)%", p.stdout, re.M)
            self.assertEqual([r[0] for r in rows], ["first_prototype_6dof", "final_prototype_7dof"], p.stdout)
            self.assertEqual([r[1] for r in rows], ["6", "7"])
            for r in rows:
                self.assertTrue(0 < float(r[2]) <= 100, p.stdout)
            self.assertTrue(os.path.isfile(os.path.join(out, "compare_designs_py", "report.html")))


if __name__ == "__main__":
    unittest.main()
