"""Where a tab's camera starts (app.scene.camera): in a view too narrow for the body to clear the legend (a 1024 px
page beside the docked control panel) the body is moved right of the view's centre; a wide view is left as it was;
a camera the user has moved is never moved again."""

from __future__ import annotations

import math

import numpy as np

from app.scene import camera
from app.scene.legend import LEGEND_BOX

FOV = math.radians(75.0)  # what viser's client reports (1.309 rad)


def _body_left_px(width: float, height: float, shift: float) -> float:
    """Where the body's left reach lands on screen, by the pinhole projection of a point on the view's axis
    moved sideways: worked out here apart from the module's own formula."""
    distance = math.dist(camera.POSITION, camera.LOOK_AT)
    focal_px = 0.5 * height / math.tan(0.5 * FOV)
    return 0.5 * width + focal_px * (shift - camera.BODY_HALF_WIDTH) / distance


def test_a_narrow_view_puts_the_body_just_clear_of_the_legend():
    width, height = 700, 768  # the 3-D view of a 1024x768 page
    shift = camera.framing_shift(width, height, FOV)
    assert 0 < shift < camera.MAX_SHIFT
    legend_right = LEGEND_BOX[0] + LEGEND_BOX[2]
    assert _body_left_px(width, height, 0.0) < legend_right  # unmoved, the legend covers the body
    assert math.isclose(_body_left_px(width, height, shift), legend_right + camera.GAP_PX, abs_tol=1e-9)


def test_a_wide_view_is_not_moved_and_a_very_narrow_one_is_moved_at_most_the_cap():
    assert camera.framing_shift(1076, 900, FOV) == 0.0  # a 1400x900 page
    assert camera.framing_shift(300, 700, FOV) == camera.MAX_SHIFT
    for bad in ((0, 768, FOV), (700, -1, FOV), (700, 768, 0.0), (700, 768, math.pi), (math.nan, 768, FOV)):
        assert camera.framing_shift(*bad) == 0.0, bad


def test_the_screen_right_direction_is_perpendicular_to_the_view_and_level():
    forward = np.subtract(camera.LOOK_AT, camera.POSITION)
    assert abs(np.dot(forward, camera.SCREEN_RIGHT)) < 1e-12 and camera.SCREEN_RIGHT[2] == 0.0
    assert np.cross(forward, [0.0, 0.0, 1.0]) @ camera.SCREEN_RIGHT > 0  # right, not left


class FakeCamera:
    """viser's CameraHandle as the module uses it: a report sets the size and where the camera is; a
    server-side assignment records where it was sent (the browser's next report then says so)."""

    def __init__(self):
        object.__setattr__(self, "position", camera.POSITION)
        object.__setattr__(self, "look_at", camera.LOOK_AT)
        self.callbacks, self.sent = [], []
        self._size = None

    @property
    def image_width(self):
        assert self._size is not None  # as viser asserts before the first report
        return self._size[0]

    @property
    def image_height(self):
        assert self._size is not None
        return self._size[1]

    @property
    def fov(self):
        assert self._size is not None
        return FOV

    def on_update(self, cb):
        self.callbacks.append(cb)
        return cb

    def __setattr__(self, name, value):
        if name in ("position", "look_at") and "sent" in self.__dict__ and "callbacks" in self.__dict__:
            self.sent.append((name, tuple(value)))
        object.__setattr__(self, name, value)

    def report(self, width, height, position=None):
        self._size = (width, height)
        if position is not None:
            object.__setattr__(self, "position", position)
        for cb in self.callbacks:
            cb(self)


def test_the_camera_follows_the_view_until_the_user_moves_it():
    cam = FakeCamera()
    camera.fit_when_known(cam)
    assert cam.sent == []  # nothing reported yet: nothing to fit
    cam.report(1024, 768)  # the first report: the panel not docked yet
    assert cam.sent == []
    cam.report(700, 768)  # the docked panel narrows the view
    shift = camera.framing_shift(700, 768, FOV)
    want = np.add(camera.POSITION, -shift * camera.SCREEN_RIGHT)
    assert np.allclose(cam.position, want) and np.allclose(np.subtract(cam.look_at, cam.position),
                                                           np.subtract(camera.LOOK_AT, camera.POSITION))
    sent = len(cam.sent)
    cam.report(700, 768, position=camera.POSITION)  # a report still in flight from before the move: ours
    assert len(cam.sent) == sent
    cam.report(700, 768, position=(5.0, -1.0, 2.0))  # the user orbits
    cam.report(1076, 900, position=(5.0, -1.0, 2.0))  # and widens the window: their view stays
    cam.report(1076, 900, position=tuple(want))
    assert len(cam.sent) == sent


def test_a_camera_already_reported_is_fitted_at_once_and_one_without_reports_is_left_alone():
    cam = FakeCamera()
    cam._size = (700, 768)
    camera.fit_when_known(cam)
    assert len(cam.sent) == 2  # position and look_at
    camera.fit_when_known(object())  # a replay's or the class scene's camera: no reports, no error


def test_the_browsers_own_start_is_not_taken_for_the_users_move():
    """viser's client reports its camera on connecting; served by python -m app that first report came from
    (-5, 0, 0), before the page took this module's camera, and the camera was then left alone for good: at
    1024x768 the body stayed half under the legend. Reports seen there, in order:"""
    cam = FakeCamera()
    object.__setattr__(cam, "position", (-5.0, 0.0, 0.0))
    cam._size = (1024, 768)
    camera.fit_when_known(cam)
    cam.report(1024, 768, position=(-5.0, 0.0, 0.0))  # the page starting
    cam.report(1024, 768, position=camera.POSITION)  # it shows this module's view
    cam.report(636, 768, position=camera.POSITION)  # the docked panel narrows it
    want = np.add(camera.POSITION, -camera.framing_shift(636, 768, FOV) * camera.SCREEN_RIGHT)
    assert camera.framing_shift(636, 768, FOV) > 0 and np.allclose(cam.position, want)
    sent = len(cam.sent)
    cam.report(636, 768, position=(5.0, -1.0, 2.0))  # now a camera from elsewhere is the user's
    cam.report(1076, 900, position=(5.0, -1.0, 2.0))
    assert len(cam.sent) == sent
