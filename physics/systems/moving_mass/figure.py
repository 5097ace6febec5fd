"""The moving mass's picture (physics.figure): the rest point O1 on e3, the mass drawn at O1 plus its
displacement u, the spring between them, the mount holding O1 to the centre, the fluid cavity, and the factor u
is drawn with; and the view action that sets that factor.

u is millimetres on a body of metres, so it is drawn exaggerated by a factor chosen from the scene (the drawn
displacement stays a fraction of the body's size) and capped while drawing, so that a resonance or a large
factor cannot throw the mass off the body; the factor is written beside the mass.
"""

from __future__ import annotations

import math

import numpy as np

from physics.core.figure import Action, Ball, Segment, Text

DRAWN_FRACTION = 0.15  # the default factor draws the expected largest |u| at most this fraction of the body
CAP_FRACTION = 0.3  # whatever the factor, the drawn displacement never exceeds this fraction of the body
NICE = (1.0, 2.0, 5.0)  # the default factor is 1, 2 or 5 times a power of ten: easy to read
EXAGGERATION_MIN, EXAGGERATION_MAX = 1.0, 1000.0  # the view slider's range
LABEL_ABOVE = 0.1  # the factor's words sit this fraction of the body above O1

# sizes as fractions of the body's drawn extent: what reads as a ball, a spring, a mount at any body size
REST_SIZE, MASS_SIZE, CAVITY_SIZE = 0.025, 0.05, 0.03
SPRING_THICKNESS, MOUNT_THICKNESS = 0.008, 0.006
CAVITY_OPACITY = 0.35  # see-through: the mass and the mount show inside it


def mass_points(rho: float, u: np.ndarray, exaggeration: float) -> tuple[np.ndarray, np.ndarray]:
    """(rest point O1 = rho e3, drawn mass position O1 + exaggeration * u), body frame, m."""
    rest = np.array([0.0, 0.0, float(rho)])
    return rest, rest + exaggeration * np.asarray(u, dtype=float)


def expected_displacement(rho: float, Omega: float, omega: float) -> float:
    """The scale of the mass's displacement, m: the quasi-static answer to the largest centrifugal load on a
    point at distance rho from the centre spinning at |omega| (rad/s), held by a spring of natural frequency
    Omega (rad/s): |u| <~ |omega|^2 rho / Omega^2."""
    return float(omega) ** 2 * abs(float(rho)) / float(Omega) ** 2 if Omega > 0 else math.inf


def default_exaggeration(extent: float, rho: float, Omega: float, omega: float) -> float:
    """The factor a scene starts with: the largest 1-2-5 number that draws the expected displacement at most
    DRAWN_FRACTION of the body's size ``extent`` (m), within the slider's range."""
    u = expected_displacement(rho, Omega, omega)
    if not u > 0 or not math.isfinite(u):
        return EXAGGERATION_MIN
    want = DRAWN_FRACTION * extent / u
    if want <= EXAGGERATION_MIN:
        return EXAGGERATION_MIN
    p = 10.0 ** math.floor(math.log10(want))
    best = max(m * p for m in NICE if m * p <= want)
    return float(min(max(best, EXAGGERATION_MIN), EXAGGERATION_MAX))


def drawn_displacement(u: np.ndarray, factor: float, extent: float) -> tuple[np.ndarray, bool]:
    """(the displacement to draw, m; whether the cap cut it): factor * u, shortened to CAP_FRACTION * extent
    if longer."""
    d = float(factor) * np.asarray(u, dtype=float)
    n = float(np.linalg.norm(d))
    cap = CAP_FRACTION * extent
    if n > cap:
        return d * (cap / n), True
    return d, False


def factor_label(factor: float, capped: bool) -> str:
    """The words beside the mass: the factor its displacement is drawn with."""
    return f"u x {factor:g}" + (" (capped)" if capped else "")


def figure(sc, state: dict, view) -> tuple:
    """The cavity, O1, the mount, the mass, the spring and the factor's words, body frame, m. Without a
    displacement in ``state`` (the averaged and closed models average it away) the mass is drawn at O1."""
    out: list = []
    if sc.cavity is not None:
        out.append(Ball("cavity", "cavity", "cavity filled with viscous fluid", "cavity", moves=False,
                        opacity=CAVITY_OPACITY, radius=sc.cavity.a0, size=CAVITY_SIZE))
    if sc.mass is None:
        return tuple(out)
    moves = "ux" in state
    if moves:
        u = np.array([state["ux"], state.get("uy", 0.0), state.get("uz", 0.0)])
        drawn, capped = drawn_displacement(u, view.exaggeration, view.extent)
    else:
        drawn, capped = np.zeros(3), False
    rest, _ = mass_points(sc.mass.rho, drawn, 1.0)
    mass = (f"moving mass m; its displacement u drawn x {view.exaggeration:g}" if moves
            else "moving mass m, at rest (this fidelity averages its motion)")
    out.append(Ball("mass", "mass", mass, "part", size=MASS_SIZE, centre=rest + drawn))
    if moves:
        out.append(Segment("spring", "spring", "spring: rest point to mass", "link", a=rest, b=rest + drawn,
                           thickness=SPRING_THICKNESS))
    out.append(Ball("rest", "rest", "rest point O1, on e3 at rho", "anchor", moves=False, size=REST_SIZE,
                    centre=rest))
    out.append(Segment("mount", "mount", "mount: O1 is fixed to the body", "anchor", moves=False, b=rest,
                       thickness=MOUNT_THICKNESS))
    out.append(Text("factor", "", "", "marker", position=rest + [0.0, 0.0, LABEL_ABOVE * view.extent],
                    text=factor_label(view.exaggeration, capped)))
    return tuple(out)


def _initial_exaggeration(sc, extent: float, omega) -> float:
    m = sc.mass
    return default_exaggeration(extent, m.rho, m.Omega, float(np.linalg.norm(omega)))


ACTIONS = (
    Action("exaggeration", "exaggerate u (x)", "view", "View", key="exaggeration", lo=EXAGGERATION_MIN,
           hi=EXAGGERATION_MAX, step=1.0, initial=_initial_exaggeration, shown=lambda sc: sc.mass is not None,
           hint="the mass's displacement is drawn this many times larger (each scene starts with a factor that "
           "keeps it within the body; shown beside the mass)"),
)
