"""The viscous wheel damper's picture (``System.figure``): the wheel as a disk turning on its axle.

J alone gives the wheel no radius, so the disk is drawn at a fixed fraction of the body's drawn extent, centred
at the body's centre where it reads as inside the body, its normal the wheel's axis and its mark turned by the
wheel's angle relative to the body.
"""

from __future__ import annotations

import math

import numpy as np

from physics.core.figure import Disk, Segment

RADIUS = 0.25  # x the body's extent: the disk's drawn radius
AXLE = 0.4  # x the body's extent: the axle's half length, through the disk


def _reference(a: np.ndarray) -> np.ndarray:
    """A unit vector normal to the axis a: the disk's zero angle (the body axis least aligned with a, made normal)."""
    e = np.eye(3)[int(np.argmin(np.abs(a)))]
    r = e - (e @ a) * a
    return r / np.linalg.norm(r)


def figure(sc, state: dict, view) -> tuple:
    """A Disk "wheel" (normal = the axis, angle = the wheel's angle phi_w, 0 when the state has none) and a
    Segment "axle", in body coordinates (m)."""
    a = np.array(sc.wheel.axis, dtype=float)
    extent = float(view.extent) if math.isfinite(view.extent) and view.extent > 0 else 1.0
    angle = float(state.get("phi_w", 0.0)) if state else 0.0
    if not math.isfinite(angle):
        angle = 0.0
    angle = math.remainder(angle, 2.0 * math.pi)  # a wheel that has turned for hours: the same picture, finite
    return (
        Disk(name="wheel", role="wheel", label="wheel damper: turns at its rate relative to the body", colour="wheel",
             centre=(0.0, 0.0, 0.0), normal=a, ref=_reference(a), radius=RADIUS * extent, angle=angle),
        Segment(name="axle", role="axle", label="the wheel's axle, fixed in the body", colour="anchor",
                a=-AXLE * extent * a, b=AXLE * extent * a, moves=False),
    )
