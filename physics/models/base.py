"""What a model is, and the one registry every consumer (simulate, the app, the test battery) reads."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..scenario import Scenario
from ..trajectory import Trajectory


@dataclass(frozen=True)
class Model:
    """A system at one fidelity.

    ``pack(scenario) -> p`` makes the parameter vector; ``initial_state(scenario, p) -> y0``;
    ``observe(t, Y, p, scenario) -> Trajectory`` turns states into output; ``invariants(Y, p)``
    gives the inertial angular momentum (n, 3) and energy (n,) that conservation tests check.
    An ODE model names its compiled kernel (``kernel``) and its state layout (``state``);
    a closed form gives ``solve(scenario, t) -> Trajectory`` instead.
    """

    name: str
    system: str
    fidelity: str
    summary: str
    state: tuple[str, ...] = ()
    kernel: int | None = None
    pack: Callable | None = None
    initial_state: Callable | None = None
    observe: Callable | None = None
    invariants: Callable | None = None
    solve: Callable[[Scenario, np.ndarray], Trajectory] | None = None
    columns: tuple[str, ...] = field(default=())

    def rhs(self, t: float, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """dy/dt as a new array (a convenience for tests and scipy; the integrators call the kernel)."""
        from ..compiled.dispatch import rhs

        out = np.empty_like(y)
        rhs(self.kernel, t, np.asarray(y, dtype=float), p, out)
        return out


REGISTRY: dict[str, Model] = {}


def register(model: Model) -> Model:
    if model.name in REGISTRY:
        raise ValueError(f"model {model.name!r} registered twice")
    REGISTRY[model.name] = model
    return model


def get_model(system: str, fidelity: str) -> Model:
    return REGISTRY[f"{system}/{fidelity}"]
