"""Where a tab's camera starts: looking down at the body from its front right, with the body moved right of the
view's centre when the view is too narrow for it to clear the legend.

The control panel is docked at the page's right edge, so the 3-D view is what remains beside it: about 1075 px
at a 1400 px page, about 700 px at 1024. The legend floats at the view's left (app.scene.legend.LEGEND_BOX, to
x = 342 px); in a 700 px view a body at the centre has its left third under it. The view's size is known once the
browser reports its camera (viser's ``image_width``); until the user moves the camera, each report places it
for the view's size.
"""

from __future__ import annotations

import math
import threading

import numpy as np

from .legend import LEGEND_BOX

POSITION = (3.0, -3.4, 1.9)
LOOK_AT = (0.0, 0.0, 0.3)
# the view's horizontal direction in the scene from that camera: forward x up, with forward (-3, 3.4, .) and up z
SCREEN_RIGHT = np.array([3.4, 3.0, 0.0]) / math.hypot(3.4, 3.0)
BODY_HALF_WIDTH = 1.0  # scene units from the centre to the inertia ellipsoid and e3's trail on screen (the body: 0.75)
GAP_PX = 10  # between the legend's right edge and the body
MAX_SHIFT = 1.25  # scene units: a narrower view (a phone) keeps the body at least partly centred
SAME_PLACE = 1e-3  # scene units: a reported camera this close to a start this module set is still that start


def framing_shift(width_px: float, height_px: float, fov_rad: float) -> float:
    """Scene units to move the camera to the left so the body's left edge clears the legend, 0 when the view
    is wide enough (or its size is not a size)."""
    if not (width_px > 0 and height_px > 0 and 0 < fov_rad < math.pi):
        return 0.0
    distance = float(np.linalg.norm(np.subtract(POSITION, LOOK_AT)))
    px_per_unit = 0.5 * height_px / (math.tan(0.5 * fov_rad) * distance)  # fov is vertical (three.js)
    legend_right = LEGEND_BOX[0] + LEGEND_BOX[2] + GAP_PX
    need = (legend_right - 0.5 * width_px) / px_per_unit + BODY_HALF_WIDTH
    return min(max(need, 0.0), MAX_SHIFT)


def place(camera) -> None:
    """The starting view (any object with ``position`` and ``look_at``: a tab's, the replay's, the class's)."""
    camera.position = POSITION
    camera.look_at = LOOK_AT


def fit_when_known(camera) -> None:
    """While the camera is where this module put it, follow the view's size as the browser reports it (the first
    report can come before the docked panel narrows the view): a narrow view moves the body clear of the legend.
    A report from anywhere else, once the browser has shown this module's view, is the user's own view, which is
    then left alone for good. A camera that reports nothing (the replay's, the class scene's) stays as placed."""
    if not hasattr(camera, "on_update"):
        return
    lock = threading.Lock()  # viser runs camera callbacks in a thread pool
    ours = [np.array(POSITION, dtype=float)]  # every start this module has set (a report may lag a move)
    moved_by_user = []
    shown_ours = []  # the browser has reported a camera this module set: from then on another one is the user's

    def fit(cam, reported: bool = True) -> None:
        with lock:
            if moved_by_user:
                return
            try:
                size = float(cam.image_width), float(cam.image_height), float(cam.fov)
                at = np.asarray(cam.position, dtype=float)
            except (AssertionError, AttributeError, TypeError, ValueError):  # no report yet, or not numbers
                return
            if min(np.linalg.norm(at - p) for p in ours) > SAME_PLACE:
                # viser's client reports its camera on connecting, sometimes before it has taken this module's
                # (at (-5, 0, 0), served by python -m app): that is the page starting, not the user's move
                if shown_ours:
                    moved_by_user.append(True)
                return
            if reported:
                shown_ours.append(True)
            target = np.add(POSITION, -framing_shift(*size) * SCREEN_RIGHT)
            if np.linalg.norm(target - ours[-1]) > SAME_PLACE:
                ours.append(target)
                cam.position = tuple(target)
                cam.look_at = tuple(np.add(LOOK_AT, target - np.asarray(POSITION)))

    camera.on_update(fit)
    fit(camera, reported=False)  # the browser may have reported its size before this tab's scene was built
