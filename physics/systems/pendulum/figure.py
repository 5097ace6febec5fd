"""The pendulums' pictures (physics.figure): each bob on its arm from its pivot, in the body frame; and the
actions the pendulum systems add to the explorer: tune the spring to resonance, the spherical pendulum's pivot,
and which plane pendulum the sliders edit.
"""

from __future__ import annotations

import math

import numpy as np

from physics.core.figure import Action, Ball, Segment
from physics.systems.pendulum.params import PIVOTS

BOB_SIZE = 0.04  # the bob's drawn radius, a fraction of the body's drawn extent
ARM_THICKNESS = 0.012
FOLDER = "Pendulum damper"
E3 = np.array([0.0, 0.0, 1.0])


def spherical_bob(h: float, l: float, alpha: float, beta: float,
                  chart: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(pivot h e3, bob pivot + l e) with e = R_x(alpha) R_y(beta) e3 in chart 0, e = R_y(alpha) R_x(beta) e3 in
    chart 1 (the angles the run uses near chart 0's pole, physics/compiled/pendulum.py)."""
    sa, ca, sb, cb = math.sin(alpha), math.cos(alpha), math.sin(beta), math.cos(beta)
    e = np.array([sb, -sa * cb, ca * cb]) if chart < 0.5 else np.array([sa * cb, -sb, ca * cb])
    pivot = h * E3
    return pivot, pivot + l * e


def plane_bob(hinge, axis, arm, l: float, a: float) -> tuple[np.ndarray, np.ndarray]:
    """(hinge, bob hinge + l (cos a e0 + sin a f)), f = n x e0 (physics/compiled/pendulum.py)."""
    n = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    e0 = np.asarray(arm, dtype=float) / np.linalg.norm(arm)
    f = np.cross(n, e0)
    hinge = np.asarray(hinge, dtype=float)
    return hinge, hinge + l * (math.cos(a) * e0 + math.sin(a) * f)


def _bobs(arms: list[tuple[np.ndarray, np.ndarray]], label: str) -> tuple:
    """Each bob (role "bob": one legend line for all) and its arm (no legend line of its own)."""
    out: list = []
    for i, (pivot, bob) in enumerate(arms):
        out.append(Ball(f"bob{i}", "bob", label, "part", size=BOB_SIZE, centre=bob))
        out.append(Segment(f"arm{i}", "", "", "link", a=pivot, b=bob, thickness=ARM_THICKNESS))
    return tuple(out)


def spherical_figure(sc, state: dict, view) -> tuple:
    """The bob at the angles alpha, beta of ``state`` (in its chart), hanging along e3 without them (the
    averaged model)."""
    if sc.pendulum is None:
        return ()
    p = sc.pendulum
    arm = spherical_bob(p.h, p.l, state.get("alpha", 0.0), state.get("beta", 0.0), state.get("chart", 0.0))
    return _bobs([arm], "spherical pendulum bob (1) on its arm")


def plane_figure(sc, state: dict, view) -> tuple:
    """Pendulum i at the angle a{i+1} of ``state`` from its rest direction, about its hinge axis."""
    n = len(sc.plane_pendulums)
    if n == 0:
        return ()
    arms = [plane_bob(*pp.geometry(), pp.l, state.get(f"a{i + 1}", 0.0)) for i, pp in enumerate(sc.plane_pendulums)]
    what = "pendulum bobs" if n > 1 else "pendulum bob"
    return _bobs(arms, f"{what} ({n}) on {'their arms' if n > 1 else 'its arm'}")


TUNE = Action("tune", "Tune to resonance", "button", FOLDER,  # under the spring it sets (docs/guide.md)
              hint="spherical pendulum: k = resonant (docs/models.md B.5)",
              apply=lambda sc: {"pendulum.k": "resonant"}, shown=lambda sc: sc.pendulum is not None)
PIVOT = Action("pivot", "pivot", "choice", FOLDER, key="pendulum.pivot", options=tuple(PIVOTS),
               value_of=lambda sc: sc.pendulum.pivot if sc.pendulum is not None else PIVOTS[0],
               shown=lambda sc: sc.pendulum is not None,
               hint="what the spring and damper act on: cardan, the two gimbal angles (the paper's model; a swing "
               "through the gimbal pole stops with a spring); isotropic, the arm's direction (the same for small "
               "swings, and it goes on through the pole)")
BOB = Action("bob", "bob", "item", FOLDER,
             options_of=lambda sc: tuple(str(i + 1) for i in range(len(sc.plane_pendulums))),
             shown=lambda sc: len(sc.plane_pendulums) > 0, hint="plane pendulums: which bob the sliders above edit")

SPHERICAL_ACTIONS = (TUNE, PIVOT)
PLANE_ACTIONS = (BOB,)
