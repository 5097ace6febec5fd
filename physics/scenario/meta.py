"""The parameters every scenario has, whatever its internal part: the body's inertia and the initial state.

Their metadata (unit, range, meaning, equation, the explorer's folder) sits here beside the tables they
describe (``physics.scenario.params``), as each System's own parameters sit in its folder. ``base_values``
is what their sliders show for a scenario.
"""

from __future__ import annotations

from physics.registry import Param
from physics.scenario.initial import initial_G

BODY_FOLDER, INITIAL_FOLDER = "Body inertia", "Initial state"
BASE_FOLDERS = (BODY_FOLDER, INITIAL_FOLDER)

BASE_PARAMS: tuple[Param, ...] = (
    Param("body.A", "A", "kg m^2", "equatorial principal moment of the frozen system (carrier + parts at rest)", 0.1,
          5.0, 0.01, "docs/models.md A.1: J* = diag(A, B, C), frozen system", BODY_FOLDER),
    Param("body.B", "B", "kg m^2", "second equatorial moment; B = A is a symmetric body", 0.1, 5.0, 0.01,
          "docs/models.md A.1: J* = diag(A, B, C), frozen system", BODY_FOLDER),
    Param("body.C", "C", "kg m^2", "axial moment; C > A oblate (settles to spin), C < A prolate (flat spin)", 0.1,
          5.0, 0.01, "docs/models.md A.1: J* = diag(A, B, C), frozen system", BODY_FOLDER),
    Param("body.M", "M", "kg", "total mass of the system", 0.1, 20.0, 0.1, "docs/models.md A.1: M = M0 + m",
          BODY_FOLDER),
    # the start: a change means something only from t = 0
    Param("initial.G0", "G0", "kg m^2/s", "initial angular momentum of the body frozen with its parts at rest, "
          "|J* w0| (the readout |K| adds what the moving parts carry); it defines the start, so changing it "
          "restarts the run from t = 0", 0.1, 10.0, 0.01, "docs/models.md A.1: G = |J* w|", INITIAL_FOLDER,
          restarts=True),
    Param("initial.theta0", "theta0", "rad", "initial nutation angle between K and e3; it defines the start, "
          "so changing it restarts from t = 0", 0.0, 3.14, 0.01, "docs/models.md A.1: C r = G cos(theta)",
          INITIAL_FOLDER, restarts=True),
)


def base_values(sc) -> dict[str, float]:
    """The body's moments and mass and the start as G0, theta0 (an ``omega`` given in the file rewritten)."""
    _, G0, theta0 = initial_G(sc)
    b = sc.body
    return {"body.A": b.A, "body.B": b.B, "body.C": b.C, "body.M": b.M, "initial.G0": G0, "initial.theta0": theta0}
