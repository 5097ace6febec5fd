"""Parameter sets of a scenario: frozen dataclasses in SI units, validated on construction.

Names follow seed 004 and docs/models.md Part A section 1 (``rho``, ``Omega``, ``chi``,
``lambda_``...). Each class validates itself in ``__post_init__`` and raises ScenarioError naming
the TOML key (``table.key``), so the same message reaches a scenario file, the CLI and the API.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field

from physics.core.errors import ScenarioError

FIDELITIES = ("auto", "full", "averaged", "closed")
METHODS = ("auto", "DOP853", "RK45", "Radau", "BDF", "LSODA", "RK4", "RK8", "midpoint")
FIXED_STEP_METHODS = ("RK4", "RK8", "midpoint")  # compiled fixed-step methods: they need run.dt
DET_MIN, DET_MAX = 2.3e-308, 1.7e308  # the normal float range


def _number(key: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ScenarioError(key, value, "must be a number")
    try:
        x = float(value)
    except OverflowError:  # an integer beyond the largest float
        raise ScenarioError(key, value, "must be a finite number (at most 1.8e308 in size)") from None
    if not math.isfinite(x):
        raise ScenarioError(key, value, "must be a finite number")
    return x


def positive(key: str, value: object) -> float:
    x = _number(key, value)
    if x <= 0:
        raise ScenarioError(key, value, "must be > 0")
    return x


def nonneg(key: str, value: object) -> float:
    x = _number(key, value)
    if x < 0:
        raise ScenarioError(key, value, "must be >= 0")
    return x


def _choice(key: str, value: object, allowed: tuple[str, ...]) -> str:
    if value not in allowed:
        raise ScenarioError(key, value, "must be one of " + ", ".join(f'"{a}"' for a in allowed))
    return value  # type: ignore[return-value]


@dataclass(frozen=True)
class Body:
    """Principal central moments of the frozen system (carrier + masses at rest), kg m^2, and
    the total mass M, kg (docs/models.md conventions). ``B`` defaults to ``A`` (symmetric body)."""

    A: float
    C: float
    M: float
    B: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "A", positive("body.A", self.A))
        object.__setattr__(self, "C", positive("body.C", self.C))
        object.__setattr__(self, "M", positive("body.M", self.M))
        B = self.A if self.B is None else positive("body.B", self.B)
        object.__setattr__(self, "B", B)
        A, C = self.A, self.C
        # The models invert the inertia tensor: its determinant A B C must be a normal float (neither
        # overflow nor underflow), which bounds the moments' sizes together, not each one alone.
        det = A * B * C
        if not DET_MIN <= det <= DET_MAX:
            key, value = max((("body.A", A), ("body.B", B), ("body.C", C)), key=lambda kv: abs(math.log10(kv[1])))
            raise ScenarioError(key, value, f"is out of range: the product A B C = {det:.3g} of the principal "
                                f"moments (the inertia tensor's determinant) must be within [{DET_MIN:g}, {DET_MAX:g}] "
                                "(kg m^2)^3")
        # A physical inertia obeys the triangle inequality; equality is a flat plate or a rod.
        # the message names the other two keys: the value changed may be either of them (body.B = 1e-300 makes
        # body.C exceed body.A + body.B)
        for key, big, others, s in (("body.A", A, "body.B + body.C", B + C), ("body.B", B, "body.A + body.C", A + C),
                                    ("body.C", C, "body.A + body.B", A + B)):
            if big > s * (1 + 1e-12):
                raise ScenarioError(key, big, f"must not exceed the sum of the other two moments, {others} = {s:.6g}")

    @property
    def symmetric(self) -> bool:
        return self.A == self.B


# G0 and omega below the smallest normal double are subnormal: their products with sin and cos of theta0 keep a
# few bits, so the initial nutation angle is lost (G0 = 5e-324 with theta0 = 0.8 started at pi/4)
SMALLEST_RATE = sys.float_info.min


@dataclass(frozen=True)
class Initial:
    """Initial rotation: either ``omega`` (rad/s, body frame) or ``G0`` = |J* w| (kg m^2/s) with
    the nutation angle ``theta0`` (rad), the angle between G and e3 (docs/models.md conventions).
    ``mass_state`` (None when not given) is the moving mass's start, validated and read by that system
    (physics/systems/moving_mass/params.py); a key of this shared table that a system owns
    (``System.initial_keys``) is refused by the others."""

    omega: tuple[float, float, float] | None = None
    G0: float | None = None
    theta0: float | None = None
    mass_state: str | None = None  # the moving mass's (System.initial_keys)

    def __post_init__(self):
        if self.omega is not None:
            if self.G0 is not None or self.theta0 is not None:
                raise ScenarioError("initial", "omega with G0/theta0", "give either omega or G0 with theta0, not both")
            if not isinstance(self.omega, (list, tuple)) or len(self.omega) != 3:
                raise ScenarioError("initial.omega", self.omega, "must be a list of three numbers [wx, wy, wz]")
            w = tuple(_number(f"initial.omega[{i}]", v) for i, v in enumerate(self.omega))
            if not any(w):
                raise ScenarioError("initial.omega", self.omega, "must not be zero (the body must rotate)")
            if max(map(abs, w)) < SMALLEST_RATE:
                raise ScenarioError("initial.omega", self.omega, f"must have a component of at least "
                                    f"{SMALLEST_RATE:.3g} rad/s in size (the smallest normal double): below it the "
                                    "components keep too few digits to give the axis of rotation")
            object.__setattr__(self, "omega", w)
        else:
            if self.G0 is None or self.theta0 is None:
                raise ScenarioError("initial", "incomplete", "give omega = [wx, wy, wz], or both G0 and theta0")
            object.__setattr__(self, "G0", positive("initial.G0", self.G0))
            if self.G0 < SMALLEST_RATE:
                raise ScenarioError("initial.G0", self.G0, f"must be at least {SMALLEST_RATE:.3g} kg m^2/s (the "
                                    "smallest normal double): below it K's components keep too few digits to give "
                                    "theta0")
            th = _number("initial.theta0", self.theta0)
            if not 0.0 <= th <= math.pi:
                raise ScenarioError("initial.theta0", self.theta0, "must be in [0, pi] rad")
            object.__setattr__(self, "theta0", th)


MIN_SPACING = sys.float_info.min  # s: the smallest normal double, the least time between two samples


@dataclass(frozen=True)
class Run:
    """What to compute: fidelity, horizon t_end (s), optional output times, number of samples,
    relative tolerance, and the integrator ("auto" picks the compiled DOP853). ``dt`` (s) is the
    largest step of the fixed-step methods (RK4, RK8, midpoint); the adaptive ones ignore it.
    ``accuracy`` (rad, theta), if given, lets fidelity "auto" pick against it (the system's error estimates)."""

    t_end: float
    fidelity: str = "auto"
    t_eval: tuple[float, ...] | None = None
    samples: int = 1001
    rtol: float = 1e-10
    method: str = "auto"
    dt: float | None = None
    accuracy: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "t_end", positive("run.t_end", self.t_end))
        _choice("run.fidelity", self.fidelity, FIDELITIES)
        _choice("run.method", self.method, METHODS)
        if isinstance(self.samples, bool) or not isinstance(self.samples, int) or not 2 <= self.samples <= 10_000_000:
            raise ScenarioError("run.samples", self.samples, "must be a whole number from 2 to 10000000")
        rtol = _number("run.rtol", self.rtol)
        if not 1e-14 <= rtol <= 1e-2:
            raise ScenarioError("run.rtol", self.rtol, "must be in [1e-14, 1e-2]")
        object.__setattr__(self, "rtol", rtol)
        if self.accuracy is not None:
            object.__setattr__(self, "accuracy", positive("run.accuracy", self.accuracy))
        if self.dt is not None:
            dt = positive("run.dt", self.dt)
            if dt > self.t_end:
                raise ScenarioError("run.dt", self.dt, f"must not exceed run.t_end = {self.t_end:g}")
            object.__setattr__(self, "dt", dt)
        elif self.method in FIXED_STEP_METHODS:
            raise ScenarioError("run.dt", None, f'is required by the fixed-step method "{self.method}" '
                                "(the largest step, s)")
        if self.t_eval is None and self.t_end / (self.samples - 1) < MIN_SPACING:
            # subnormal spacing: the sample times repeat (t_end = 5e-324 gave scipy's "Values in `t_eval` are not
            # properly sorted" as the run's fault)
            raise ScenarioError("run.t_end", self.t_end, f"too short for {self.samples} distinct sample times: "
                                f"at least {MIN_SPACING:.3g} s between samples, so t_end >= "
                                f"{MIN_SPACING * (self.samples - 1):.3g} s at run.samples = {self.samples}")
        if self.t_eval is not None:
            if not isinstance(self.t_eval, (list, tuple)) or len(self.t_eval) < 1:
                raise ScenarioError("run.t_eval", self.t_eval, "must be a non-empty list of times")
            ts = tuple(_number(f"run.t_eval[{i}]", v) for i, v in enumerate(self.t_eval))
            if any(b <= a for a, b in zip(ts, ts[1:], strict=False)) or ts[0] < 0 or ts[-1] > self.t_end:
                raise ScenarioError("run.t_eval", self.t_eval,
                                    f"must increase strictly within [0, t_end = {self.t_end:g}]")
            object.__setattr__(self, "t_eval", ts)

    def times(self):
        import numpy as np

        if self.t_eval is not None:
            return np.asarray(self.t_eval, dtype=float)
        return np.linspace(0.0, self.t_end, self.samples)



__all__ = ["Body", "Initial", "Run", "field"]
