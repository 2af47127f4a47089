"""Shared set-up of the Python tests (run by ctest with PYTHONPATH=<build>/python and the
environment variables ARMSTUDY_SOURCE_DIR and ARMSTUDY_BINARY)."""
import os
import subprocess

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
