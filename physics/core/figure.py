"""A system's picture as plain primitives, so that a viewer draws any internal part without knowing it.

A system's ``figure(scenario, state, view)`` hook (physics/registry.py, ``System.figure``) returns a tuple of
the primitives below, in **body coordinates, metres**. ``state`` maps the run's internal coordinates to
floats (the last row's ``Trajectory.internal``: "ux", "alpha", "a1", "phi_w", ...; empty for a model that has
none), ``view`` carries the viewer's choices that change a picture (``View``). Sizes that are not physical
(a ball standing for a point mass, a segment's thickness) are fractions of the body's drawn extent, so that a
part reads the same on any body.

Every primitive has a stable ``name`` (unique within one figure: a viewer keeps one drawn object per name and
moves it frame by frame), a ``role`` (the legend's key: one legend line per role), a ``label`` (that line's
words; an empty role puts no line in the legend: an arm beside its bob, a factor's words) and a ``colour`` key
from ``COLOURS`` (the viewer's palette names; a viewer may map a key to its own shade). ``moves``: the
primitive changes with the state (False: it changes only with the parameters). ``opacity`` below 1 draws it
see-through: a translucent ball is a shell (a cavity), and the legend marks it so. Primitives sharing a role
share its legend line, which takes the first one's label, colour and kind.

``body_extent`` is the body's drawn size that ``View.extent`` carries (a viewer that draws the body as a mesh
passes the mesh's size instead); ``row_state`` turns one row of a Trajectory's ``internal`` into a state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

COLOURS = ("part", "anchor", "link", "cavity", "wheel", "marker")  # the palette's keys a system may use


@dataclass(frozen=True)
class View:
    """What a viewer chose that changes a figure: ``extent`` the body's drawn size (m); ``exaggeration``
    the factor a small displacement is drawn with (a system's own view action sets it, 1 = true size)."""

    extent: float = 1.0
    exaggeration: float = 1.0


THIN = 0.04  # a flat plate or a thin rod is drawn this fraction of its size thick (the viewer's solid does the same)
SIZE_RANGE = (1e-150, 1e150)  # m: a drawn size is kept within, so that the drawing's scale is always finite


def body_extent(A: float, B: float, C: float, M: float) -> float:
    """The largest size (m) of the uniform solid of mass M with principal moments A, B, C that a viewer draws
    for the body: a cylinder along e3 when A = B (C = M R^2/2, A = M (3 R^2 + h^2)/12), else a box (A =
    M (b^2 + c^2)/12, ...); the largest of 2R and h, or of the sides, each at least THIN of the largest."""
    r = max(A, B, C)
    scale = min(max(math.sqrt(r) / math.sqrt(M), SIZE_RANGE[0]), SIZE_RANGE[1])  # two roots: 1/5e-324 overflows
    a, b, c = A / r, B / r, C / r
    if abs(a - b) <= 1e-9 * a:
        R = math.sqrt(2 * c)
        h = max(math.sqrt(max(12 * a - 6 * c, 0.0)), THIN * 2 * R)
        return float(max(2 * R, h) * scale)
    sides = np.sqrt(np.maximum(6.0 * np.array([b + c - a, a + c - b, a + b - c]), 0.0))
    return float(sides.max() * scale)


def row_state(internal: dict, row: int = -1) -> dict[str, float]:
    """One row of a Trajectory's ``internal`` (name -> array) as the state ``figure`` reads (name -> float)."""
    return {k: float(np.asarray(v).reshape(-1)[row]) for k, v in internal.items()}


def _vec(v) -> tuple[float, float, float]:
    a = np.asarray(v, dtype=float).reshape(3)
    return (float(a[0]), float(a[1]), float(a[2]))


@dataclass(frozen=True)
class Primitive:
    name: str
    role: str
    label: str
    colour: str
    moves: bool = True
    opacity: float = 1.0

    def points(self) -> np.ndarray:
        """Every point the primitive reaches (n, 3), body frame, m: what a test checks is finite and inside."""
        raise NotImplementedError

    def __post_init__(self):
        if self.colour not in COLOURS:
            raise ValueError(f"figure colour {self.colour!r} is not one of {COLOURS}")
        if not 0.0 < self.opacity <= 1.0:
            raise ValueError(f"figure {self.name!r}: opacity {self.opacity!r} is not in (0, 1]")


@dataclass(frozen=True)
class Ball(Primitive):
    """A ball at ``centre`` of radius ``radius`` m, drawn no smaller than ``size`` x the body's extent."""

    centre: tuple[float, float, float] = (0.0, 0.0, 0.0)
    radius: float = 0.0
    size: float = 0.05

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "centre", _vec(self.centre))

    def points(self) -> np.ndarray:
        return np.array([self.centre])


@dataclass(frozen=True)
class Segment(Primitive):
    """A straight segment from ``a`` to ``b`` (a spring, an arm, a mount), ``thickness`` x the body's extent."""

    a: tuple[float, float, float] = (0.0, 0.0, 0.0)
    b: tuple[float, float, float] = (0.0, 0.0, 0.0)
    thickness: float = 0.01

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "a", _vec(self.a))
        object.__setattr__(self, "b", _vec(self.b))

    def points(self) -> np.ndarray:
        return np.array([self.a, self.b])


@dataclass(frozen=True)
class Disk(Primitive):
    """A thin disk at ``centre`` with unit ``normal``, radius ``radius`` m (drawn no smaller than ``size`` x the
    body's extent), turned by ``angle`` rad about its normal from the reference direction ``ref`` (a unit
    vector normal to ``normal``): a viewer marks the angle so that a turning wheel is seen to turn."""

    centre: tuple[float, float, float] = (0.0, 0.0, 0.0)
    normal: tuple[float, float, float] = (0.0, 0.0, 1.0)
    ref: tuple[float, float, float] = (1.0, 0.0, 0.0)
    radius: float = 0.0
    size: float = 0.1
    angle: float = 0.0

    def __post_init__(self):
        super().__post_init__()
        for f in ("centre", "normal", "ref"):
            object.__setattr__(self, f, _vec(getattr(self, f)))

    def points(self) -> np.ndarray:
        n, r = np.array(self.normal), np.array(self.ref)
        return np.array([self.centre, np.array(self.centre) + self.radius * r,
                         np.array(self.centre) + self.radius * np.cross(n, r)])


@dataclass(frozen=True)
class Text(Primitive):
    """Words at ``position`` (the factor a displacement is drawn with, say)."""

    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    text: str = ""

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "position", _vec(self.position))

    def points(self) -> np.ndarray:
        return np.array([self.position])


@dataclass(frozen=True)
class Action:
    """A control a system adds to the explorer beyond its parameters' sliders.

    ``kind``: "button" (``apply(scenario) -> {dotted key: value}``, the edits it makes, e.g. tune to
    resonance), "choice" (a dropdown over ``options`` that sets the text key ``key``, e.g. the pivot), "item"
    (a dropdown that picks which item of an array table the sliders edit; ``options`` computed by
    ``options_of(scenario)``) or "view" (a number in [lo, hi] passed to ``figure`` through ``View``'s field
    ``key``, e.g. the displacement exaggeration, moved in steps of ``step``; ``initial(scenario, extent, omega)``
    is the value a scene starts with, from the body's drawn size (m) and its angular velocity now (rad/s, body
    components, (3,)); without it the view keeps its value). A choice's ``value_of(scenario)`` is the option the
    scene has (a choice is kept across scenes: a scene without what it sets keeps it for a later one). An
    item's options are the items' labels, one per item; a viewer adds "every item". ``folder``: the panel
    folder it sits in (a slider folder of the system's, or the viewer's "Model" or "View"); ``hint`` one line
    for a person; ``shown(scenario)``: whether the scene has what it acts on."""

    name: str
    label: str
    kind: str
    folder: str
    hint: str = ""
    key: str = ""
    options: tuple[str, ...] = ()
    lo: float = 0.0
    hi: float = 0.0
    apply: object = None
    options_of: object = None
    step: float = 0.0
    initial: object = None
    value_of: object = None
    shown: object = field(default=lambda sc: True)

    def __post_init__(self):
        if self.kind not in ("button", "choice", "item", "view"):
            raise ValueError(f"action {self.name!r}: kind {self.kind!r} is not button, choice, item or view")
        needs = {"button": ("apply",), "choice": ("key", "options"), "item": ("options_of",), "view": ("key",)}
        missing = [f for f in needs[self.kind] if not getattr(self, f)]
        if missing:
            raise ValueError(f"action {self.name!r} ({self.kind}) needs {', '.join(missing)}")
        if self.kind == "view" and not (self.lo < self.hi and self.key in View.__dataclass_fields__):
            raise ValueError(f"action {self.name!r}: a view sets a View field in [lo, hi], lo < hi")
