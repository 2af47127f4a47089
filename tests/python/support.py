"""Shared set-up of the Python tests (run by ctest with PYTHONPATH=<build>/python and the
environment variables ARMSTUDY_SOURCE_DIR and ARMSTUDY_BINARY)."""
import json
import os
import subprocess
import sys

import numpy as np

import armstudy  # noqa: F401  (a missing module fails the test, never skips it)

SOURCE_DIR = os.environ["ARMSTUDY_SOURCE_DIR"]
BINARY = os.environ["ARMSTUDY_BINARY"]
ROBOTS_DIR = os.environ.get("ARMSTUDY_ROBOTS_DIR", os.path.join(SOURCE_DIR, "..", "shared", "robots"))
DESIGNS = ["first_prototype_6dof", "first_prototype_9dof", "final_prototype_7dof", "final_prototype_9dof"]


def design_path(name):
    return os.path.join(SOURCE_DIR, "designs", name + ".toml")


def random_configurations(design, count, seed):
    """Configurations drawn uniformly within the joint limits."""
    rng = np.random.default_rng(seed)
    return design.lower + rng.random((count, design.dof)) * (design.upper - design.lower)


def cli(*args, check=True):
    """Runs the armstudy CLI; returns (exit code, stdout, stderr)."""
    p = subprocess.run([BINARY, *args], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"armstudy {' '.join(args)} exited {p.returncode}: {p.stderr}")
    return p.returncode, p.stdout, p.stderr


def rot_xyz(alpha, beta, gamma):
    """R = Rx(alpha) Ry(beta) Rz(gamma) (docs/conventions.md)."""
    ca, sa, cb, sb, cg, sg = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta), np.cos(gamma), np.sin(gamma)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]])
    return rx @ ry @ rz


# The outcome of each call in a child process, printed as one JSON line: raised is None (the call
# returned), "InputError" (with its file, key and message) or the name of any other exception.
CHILD_PREAMBLE = """
import json, math, resource, sys
import armstudy

def outcome(call):
    try:
        call()
        return {"raised": None}
    except armstudy.InputError as e:
        return {"raised": "InputError", "file": e.file, "key": e.key, "message": e.message}
    except BaseException as e:
        return {"raised": type(e).__name__, "message": str(e)[:300]}
"""


def run_isolated(code, timeout=300, memory_bytes=None):
    """Runs `code` (after CHILD_PREAMBLE) in a child python3, so that a crash or a runaway
    allocation ends the child, not the test runner. The code prints one JSON line (json.dumps) as
    its last output; returns it parsed. A signal, another exit code or no JSON line fails."""
    limit = "" if memory_bytes is None else (
        f"resource.setrlimit(resource.RLIMIT_AS, ({memory_bytes}, {memory_bytes}))\n")
    p = subprocess.run([sys.executable, "-c", CHILD_PREAMBLE + limit + code], capture_output=True,
                       text=True, timeout=timeout)
    if p.returncode != 0:
        raise AssertionError(f"child python exited {p.returncode} (negative: killed by that signal); "
                             f"stderr: {p.stderr[-2000:]}")
    lines = p.stdout.strip().splitlines()
    if not lines:
        raise AssertionError(f"child python printed nothing; stderr: {p.stderr[-2000:]}")
    return json.loads(lines[-1])
