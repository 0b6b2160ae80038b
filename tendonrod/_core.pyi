# Type stub of the compiled core (tendonrod/_core.c and the glue tendonrod/_*.c).
# Arrays are float64 NumPy arrays of the shapes csrc/README.md ("Raw glue contract")
# gives; results are dicts keyed as it lists.  A name added to the glue and not yet here
# reads as Any (the module-level __getattr__ below) until it is typed here.
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

_F = NDArray[np.float64]

gsl_version: str
DEFAULT_OPTIONS: dict[str, Any]
LIMITS: dict[str, Any]
CHOICES: dict[str, tuple[str, ...]]
ROD_COLUMNS: tuple[str, ...]
TENDON_COLUMNS: tuple[str, ...]
LOAD_COLUMNS: tuple[str, ...]
PARAM_KINDS: tuple[str, ...]
STATUS_CONFIRMED: int
STATUS_EBUDGET: int
STATUS_EINTERRUPTED: int
STATUS_OFFPATH: int
STATUS_TRUNCATION: int
STATUS_FRICTION_HELD: int
STATUS_UNSTABLE: int

class Cancel:
    """A token that stops the solves given it (``cancel=``) when set from another thread."""

    def __init__(self) -> None: ...
    def set(self) -> None: ...
    def clear(self) -> None: ...
    @property
    def is_set(self) -> bool: ...

class Problem:
    """A compiled scene structure, solved warm (``tr_model`` + ``tr_data``)."""

    def __init__(
        self,
        rod: ArrayLike,
        tendons: ArrayLike,
        loads: ArrayLike,
        dist: ArrayLike,
        *,
        dloads: ArrayLike | None = ...,
        **options: Any,
    ) -> None: ...
    @property
    def breakpoints(self) -> _F: ...
    @property
    def formulation(self) -> dict[str, Any]: ...
    @property
    def has_solution(self) -> bool: ...
    @property
    def last_success(self) -> bool: ...
    def set_values(
        self,
        *,
        values: ArrayLike | None = ...,
        point_loads: ArrayLike | None = ...,
        dist: ArrayLike | None = ...,
        pretension: ArrayLike | None = ...,
    ) -> None: ...
    def set_value_vector(self, v: ArrayLike) -> None: ...
    def solve(
        self,
        *,
        guess: ArrayLike | None = ...,
        jacobian: ArrayLike | None = ...,
        verified: tuple[int, float, ArrayLike]
        | tuple[int, float, ArrayLike, ArrayLike | None]
        | None = ...,
        warm: bool = ...,
        cancel: Cancel | None = ...,
        record: bool = ...,
        **kwargs: Any,
    ) -> dict[str, Any]: ...
    def record_from(self, unknowns: ArrayLike, steps: int) -> dict[str, Any]: ...
    def compliance(self, s: float, *, cancel: Cancel | None = ...) -> _F: ...
    def linearize(
        self,
        params: ArrayLike,
        rows: ArrayLike,
        *,
        forward: bool = ...,
        unknowns: ArrayLike | None = ...,
        steps: int = ...,
        side: ArrayLike | None = ...,
        cancel: Cancel | None = ...,
    ) -> dict[str, Any]: ...
    def set_target(self, kind: int, values: ArrayLike, tendons: ArrayLike) -> None: ...
    def actuate(
        self,
        *,
        kind: int,
        tendons: ArrayLike,
        c0: ArrayLike,
        scale: ArrayLike,
        values: ArrayLike,
        floor: ArrayLike,
        tau_scale: float,
        k: float,
        tol: float,
        max_iter: int,
        tip_row: int,
        goal: int,
        length: float,
        theta: float = ...,
        direction: ArrayLike | None = ...,
        basis: ArrayLike | None = ...,
        position: ArrayLike | None = ...,
        rotation: ArrayLike | None = ...,
        rows: ArrayLike | None = ...,
        augmented: bool = ...,
        judge: bool = ...,
        cancel: Cancel | None = ...,
    ) -> dict[str, Any]: ...
    def stability(self, unknowns: ArrayLike, steps: int, quick: bool = ...) -> dict[str, Any]: ...
    def forget(self) -> None: ...

def solve(
    rod: ArrayLike,
    tendons: ArrayLike,
    loads: ArrayLike,
    dist: ArrayLike,
    *,
    guess: ArrayLike | None = ...,
    jacobian: ArrayLike | None = ...,
    cancel: Cancel | None = ...,
    **options: Any,
) -> dict[str, Any]: ...
def solve_batch(
    rod: ArrayLike, tendons: ArrayLike, loads: ArrayLike, dist: ArrayLike, **kwargs: Any
) -> dict[str, Any]: ...
def compliance(
    rod: ArrayLike,
    tendons: ArrayLike,
    loads: ArrayLike,
    dist: ArrayLike,
    s: float,
    *,
    guess: ArrayLike | None = ...,
    **options: Any,
) -> _F: ...
def is_planar(
    tendons: ArrayLike,
    loads: ArrayLike,
    dist: ArrayLike,
    dloads: ArrayLike | None = ...,
    sections: ArrayLike | None = ...,
    routes: ArrayLike | None = ...,
) -> bool: ...
def strerror(status: int) -> str: ...
def qp(
    H: ArrayLike,
    g: ArrayLike,
    A: ArrayLike,
    G: ArrayLike,
    h: ArrayLike,
    x0: ArrayLike,
    max_iter: int = ...,
) -> tuple[_F, _F, _F, tuple[int, ...]]: ...
def modes(
    problem: Problem,
    unknowns: ArrayLike,
    steps: int,
    n: int,
    mass: ArrayLike,
    point_masses: ArrayLike,
    *,
    elements: int = ...,
    levels: int = ...,
    rotary: bool = ...,
    cancel: Cancel | None = ...,
) -> dict[str, Any]: ...
def simulate(
    problem: Problem,
    unknowns: ArrayLike,
    values: ArrayLike,
    loads: ArrayLike | None,
    dt: float,
    *,
    alpha: float = ...,
    rho_a: float = ...,
    rho_j: ArrayLike = ...,
    eta: float = ...,
    drag: float = ...,
    max_iter: int = ...,
    backbone: bool = ...,
    resume: ArrayLike | None = ...,
    dist0: ArrayLike | None = ...,
    cancel: Cancel | None = ...,
) -> dict[str, Any]: ...

# the closed forms of the paper (csrc/tr_closed.c), NumPy ufuncs
deflection: np.ufunc
angle: np.ufunc
tension: np.ufunc
equivalent_stiffness: np.ufunc
pattern_factor: np.ufunc
actuation_tension_for_angle: np.ufunc
actuation_tension_for_deflection: np.ufunc

def __getattr__(name: str) -> Any: ...
