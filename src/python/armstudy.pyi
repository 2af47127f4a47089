# Typed stub of the armstudy extension module (docs/python.md). Arrays are float64 numpy arrays;
# "N" is the batch axis, dropped when a single configuration (dof,) or pose (6,) is given.
import os
from typing import Any, Callable, Mapping, Optional, Sequence, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str
__revision__: str
STATUS_NAMES: list[str]

ArrayLike = npt.ArrayLike
PathLike = Union[str, os.PathLike[str]]
Array = npt.NDArray[np.float64]

class InputError(ValueError):
    file: str
    line: int
    key: str
    message: str

class SolveResult(TypedDict):
    status: int
    status_name: str
    reachable: bool
    q: Array
    manipulability: float
    position_error: float
    orientation_error: float
    joint_limit_margin: float
    starts: int
    iterations: int
    min_distance: float
    colliding_pair: str

class BatchSolveResult(TypedDict):
    status: npt.NDArray[np.uint8]
    status_name: list[str]
    reachable: npt.NDArray[np.bool_]
    q: Array
    manipulability: Array
    position_error: Array
    orientation_error: Array
    joint_limit_margin: Array
    starts: npt.NDArray[np.int32]
    iterations: npt.NDArray[np.int32]
    min_distance: Array
    colliding_pair: list[str]

class Design:
    @property
    def name(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def file(self) -> str: ...
    @property
    def file_hash(self) -> str: ...
    @property
    def assumptions(self) -> list[str]: ...
    @property
    def warnings(self) -> list[str]: ...
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def joints(self) -> list[dict[str, Any]]: ...
    @property
    def lower(self) -> Array: ...
    @property
    def upper(self) -> Array: ...
    @property
    def max_velocity(self) -> Array: ...
    @property
    def tcp(self) -> dict[str, float]: ...
    @property
    def base(self) -> dict[str, float]: ...
    @property
    def tool_axis(self) -> Array: ...
    @property
    def payload_kg(self) -> float: ...
    @property
    def has_inertia(self) -> bool: ...
    @property
    def volumes(self) -> list[dict[str, Any]]: ...
    @property
    def collision_pairs(self) -> list[tuple[str, str]]: ...
    def to_toml(self) -> str: ...
    def to_urdf(self) -> str: ...
    def with_entries(self, entries: Mapping[str, float], name: str = "") -> Design: ...
    def fk(self, q: ArrayLike, threads: int = 0) -> Array: ...
    def frames(self, q: ArrayLike, threads: int = 0) -> Array: ...
    def jacobian(self, q: ArrayLike, threads: int = 0) -> Array: ...
    def task_jacobian(self, q: ArrayLike, task: str = "full", threads: int = 0) -> Array: ...
    def manipulability(self, q: ArrayLike, task: str = "full", threads: int = 0) -> Array: ...
    def inverse_dynamics(
        self,
        q: ArrayLike,
        qd: Optional[ArrayLike] = None,
        qdd: Optional[ArrayLike] = None,
        gravity: Optional[Sequence[float]] = None,
        payload: bool = True,
        rotor_inertia: bool = False,
        threads: int = 0,
    ) -> Array: ...
    def mass_matrix(self, q: ArrayLike, rotor_inertia: bool = False, threads: int = 0) -> Array: ...
    def self_distances(self, q: ArrayLike, threads: int = 0) -> Array: ...
    def solve(
        self,
        target: ArrayLike,
        task: str = "full",
        axis: Optional[ArrayLike] = None,
        pose_id: int = 0,
        warm_start: Optional[ArrayLike] = None,
        self_collision: bool = False,
        position_tolerance: float = 0.001,
        orientation_tolerance: float = 0.008726646259971648,
        max_starts: int = 64,
        seed: int = 1,
    ) -> SolveResult: ...
    def solve_batch(
        self,
        targets: ArrayLike,
        task: str = "full",
        axis: Optional[ArrayLike] = None,
        pose_ids: Optional[ArrayLike] = None,
        warm_starts: Optional[ArrayLike] = None,
        threads: int = 0,
        self_collision: bool = False,
        position_tolerance: float = 0.001,
        orientation_tolerance: float = 0.008726646259971648,
        max_starts: int = 64,
        seed: int = 1,
    ) -> BatchSolveResult: ...

class StudyResult(dict[str, Any]):
    def answer(self) -> str: ...
    def first_map(self) -> Optional[str]: ...
    def _repr_html_(self) -> str: ...

def pose_to_matrix(pose: ArrayLike) -> Array: ...
def matrix_to_pose(matrix: ArrayLike) -> Array: ...
def make_transform(
    position: ArrayLike, rotation: Optional[ArrayLike] = None, quaternion: Optional[ArrayLike] = None
) -> Array: ...
def matrix_to_quaternion(matrix: ArrayLike) -> Array: ...
def spray_direction(alpha: ArrayLike, gamma: ArrayLike) -> Array: ...
def direction_to_angles(direction: ArrayLike) -> Array: ...
def load_design(
    path: PathLike,
    base: str = "",
    tip: str = "",
    packages: Mapping[str, PathLike] = ...,
    collision: bool = True,
) -> Design: ...
def parse_design(text: str, label: str = "<string>") -> Design: ...
def read_map(path: PathLike) -> dict[str, Any]: ...
def check_study(study: Union[PathLike, Mapping[str, Any]], folder: PathLike = ".") -> dict[str, Any]: ...
def run_study(
    study: Union[PathLike, Mapping[str, Any]],
    output: PathLike = "output",
    threads: int = 0,
    overwrite: bool = False,
    unit_size: int = 0,
    folder: PathLike = ".",
    preview: int = 0,
    on_preview: Optional[Callable[[str], Any]] = None,
) -> StudyResult: ...
def synthesize_tcp(
    design: Design,
    rows: int = 60,
    noise: float = 1e-4,
    orientation: bool = False,
    noise_angle: float = 1e-4,
    hidden: Sequence[str] = ...,
    seed: int = 1,
) -> dict[str, Any]: ...
def compare(
    design: Design,
    data: Union[PathLike, ArrayLike],
    kind: str = "tcp",
    pose: Optional[ArrayLike] = None,
    joint: str = "",
    variable_bins: int = 4,
    workspace_bins: int = 4,
    speed_bins: int = 8,
    load_bins: int = 4,
) -> dict[str, Any]: ...
def fit(
    design: Design,
    data: Union[PathLike, ArrayLike],
    kind: str = "tcp",
    pose: Optional[ArrayLike] = None,
    joint: str = "",
    add: Sequence[str] = ...,
    auto: bool = False,
    folds: int = 5,
    seed: int = 1,
    variable_bins: int = 4,
    workspace_bins: int = 4,
    speed_bins: int = 8,
    load_bins: int = 4,
) -> dict[str, Any]: ...
