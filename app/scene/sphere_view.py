"""The momentum sphere in one tab's scene, beside the body: K's direction in body axes on a translucent sphere,
the frozen body's polhodes (app.engine.sphere), the separatrix through the intermediate axis, and the path K's tip
has taken, ending in a ball at K now, and the target the energy sink leads K to (physics.end_state: the axis of
largest moment of the system locked in its end configuration), a purple ball labelled "end", hidden when the
scene has no fixed end. The sphere's axes are the body's e1, e2, e3 (e3 up), fixed on screen.

The curves are rebuilt only when A, B, C change; the path is resent only when it grew, at the plots' rate.
"""

from __future__ import annotations

import numpy as np

from ..engine import sphere
from ..handles import set_if_changed
from .legend import AXIS_COLORS, COLORS

RADIUS = 0.62  # scene units: a bit smaller than the body (app.scene.drawing.SCENE_SIZE = 1.5 across)
# in front of the body and to its lower left on screen from the starting camera (app.scene.drawing: camera at
# (3, -3.4, 1.9) looking at (0, 0, 0.3), 75 degrees of view): the panel covers the page's right and the legend
# its upper left (app.scene.legend.LEGEND_BOX, down to y = 490 px); here the sphere is centred near (270, 625) px at
# 1024x768 and (416, 732) px at 1400x900, about 95 and 110 px in radius, just above the grid (z = -1.4)
POSITION = (0.09, -2.52, -0.7)
LIFT = 1.004  # curves drawn just outside the sphere: on its surface they would flicker with it (depth fight)
PATH_LIFT = 1.015  # K's path outside the curves: a free body's K runs along one of them (the flip: the separatrix)
SPHERE_COLOR = (225, 228, 235)
# the legend's "sphere_curves" line shows these three (app.scene.legend)
STABLE_COLOR = (40, 110, 200)  # polhodes about the axis of largest moment, where dissipation sends K
OTHER_COLOR = (235, 150, 40)  # polhodes about the axis of smallest moment
SEPARATRIX_COLOR = (215, 30, 30)
AXIS_NAMES = ("e1", "e2", "e3")
END_COLOR = (148, 103, 189)  # as the E plot's E_end line (app.panel.energy_plot.END_COLOR) and the legend's
CURVE_THICKNESS = 0.009  # scene units; the separatrix and K's path are drawn thicker


class SphereView:
    """The momentum sphere of one tab (scene nodes under ``{root}_sphere``)."""

    def __init__(self, scene, root: str, engine):
        self.scene = scene
        self.engine = engine
        self.name = f"{root}_sphere"
        self.frame = scene.add_frame(self.name, show_axes=False, position=POSITION,
                                     visible=bool(getattr(engine, "show_sphere", True)))
        r = RADIUS
        scene.add_icosphere(f"{self.name}/shell", radius=r, color=SPHERE_COLOR, opacity=0.35, subdivisions=4,
                            cast_shadow=False, receive_shadow=False)
        ends = np.array([[[-1.18 * r * (i == j) for j in range(3)], [1.18 * r * (i == j) for j in range(3)]]
                         for i in range(3)])
        scene.add_line_segments(f"{self.name}/axes", ends, np.array(AXIS_COLORS, dtype=np.uint8)[:, None, :]
                                .repeat(2, axis=1), thickness=0.008)
        for i, label in enumerate(AXIS_NAMES):
            scene.add_label(f"{self.name}/axis_{label}", label, position=tuple(1.25 * r * np.eye(3)[i]),
                            font_screen_scale=0.7, anchor="center-center")
        self.title = scene.add_label(f"{self.name}/title", "K in body axes", position=(0.0, 0.0, -1.3 * r),
                                     font_screen_scale=0.8, anchor="top-center")  # under it: clear of the legend
        self.curves = scene.add_line_segments(f"{self.name}/polhodes", np.zeros((1, 2, 3)), STABLE_COLOR,
                                              thickness=CURVE_THICKNESS)
        self.separatrix = scene.add_line_segments(f"{self.name}/separatrix", np.zeros((1, 2, 3)), SEPARATRIX_COLOR,
                                                  thickness=0.010, visible=False)
        self.sep_label = scene.add_label(f"{self.name}/separatrix_label", "separatrix", font_screen_scale=0.65,
                                         anchor="bottom-left", visible=False)
        self.path = scene.add_line_segments(f"{self.name}/path", np.zeros((1, 2, 3)), COLORS["K"], thickness=0.02)
        self.tip = scene.add_icosphere(f"{self.name}/tip", radius=0.045, color=COLORS["K"])
        self.end = scene.add_icosphere(f"{self.name}/end", radius=0.05, color=END_COLOR, visible=False)
        self.end_label = scene.add_label(f"{self.name}/end_label", "end", font_screen_scale=0.65,
                                         anchor="bottom-left", visible=False)
        self._moments = None
        self._end_at: tuple | None = None
        self._drawn = 0  # sets of curves drawn so far
        self._version = -1

    def _redraw_curves(self, moments: tuple[float, float, float]) -> None:
        r = RADIUS * LIFT
        order = np.argsort(moments, kind="stable")
        curves = sphere.polhodes(moments)
        pts = sphere.segments([c for _, _, c in curves]) * r
        colors = np.empty(pts.shape, dtype=np.uint8)
        colors[:] = STABLE_COLOR
        at = 0
        for _, axis, c in curves:  # blue about the axis of largest moment (where dissipation sends K), else orange
            colors[at:at + len(c) - 1] = STABLE_COLOR if axis == order[2] else OTHER_COLOR
            at += len(c) - 1
        # a node's colours are fixed at creation: a new set of curves is a new node, under a new name (one removed
        # and added again under its name in one message batch did not show)
        self.curves.remove()
        self._drawn += 1
        self.curves = self.scene.add_line_segments(f"{self.name}/polhodes{self._drawn}", pts, colors,
                                                   thickness=CURVE_THICKNESS)
        seps = sphere.separatrices(moments)
        set_if_changed(self.separatrix, "visible", bool(seps))
        set_if_changed(self.sep_label, "visible", bool(seps))
        if seps:
            self.separatrix.points = sphere.segments(seps) * r
            mid = np.eye(3)[order[1]]
            self.sep_label.position = tuple(1.02 * r * mid)

    def update(self, fr, plots_now: bool) -> None:
        """Show or hide it as the panel says; new curves when A, B, C changed; K now; the path when it grew."""
        eng = self.engine
        shown = bool(getattr(eng, "show_sphere", True))
        set_if_changed(self.frame, "visible", shown)
        if not shown:
            return
        b = eng.scenario.body
        moments = (float(b.A), float(b.B), float(b.C))
        if moments != self._moments:
            self._moments = moments
            self._redraw_curves(moments)
        path = eng.sphere_path
        tip = path.now
        if tip is not None:
            self.tip.position = tuple(RADIUS * PATH_LIFT * tip)
        end = eng.end_state()
        set_if_changed(self.end, "visible", bool(end))
        set_if_changed(self.end_label, "visible", bool(end))
        if end:
            at = tuple(float(x) for x in RADIUS * PATH_LIFT * end.axis)
            if at != self._end_at:
                self._end_at = at
                self.end.position = at
                self.end_label.position = tuple(1.1 * x for x in at)
        if plots_now and path.version != self._version:
            self._version = path.version
            self.path.points = sphere.path_segments(path.values()) * (RADIUS * PATH_LIFT)
