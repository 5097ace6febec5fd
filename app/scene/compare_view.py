"""The second body of compare mode (app.engine.compare) in one tab's scene: its shape, translucent and in another
colour, its system's figure (app.scene.figure_view, dimmed), its K, omega and e3 arrows, and a label naming its
difference. Beside the
first body (to its right on screen, the momentum sphere being on the left) or superimposed on it: beside is
the default, as two translucent bodies in one place with six arrows are hard to tell apart until they
diverge; superimposed shows the divergence itself, from one shared start.
"""

from __future__ import annotations

import numpy as np

from ..engine.compare import PLACES, frame_of
from ..engine.geometry import box_mesh, cylinder_mesh
from ..handles import set_if_changed
from .figure_view import FigureNodes
from .legend import COLORS

# to the right of the first body on screen from the starting camera (screen right is about (0.75, 0.66, 0):
# app.scene.sphere_view), a little further back so the panel on the page's right does not cover it
OFFSETS = {"beside": (1.3, 0.9, 0.0), "superimposed": (0.0, 0.0, 0.0)}
BODY_COLOR = (235, 140, 50)  # the second body: orange, against the first's blue
ARROW_TINT = 0.45  # the second body's arrows: the first's colours mixed this much with white
OPACITY = 0.3
PART_OPACITY, PART_SCALE = 0.7, 0.9  # its parts: see-through and a little smaller than the first body's


def _tint(color) -> tuple[int, int, int]:
    return tuple(int(c + ARROW_TINT * (255 - c)) for c in color)


class CompareView:
    """Scene nodes under ``{root}_cmp``; rebuilt when the comparison, its shape or its parts change."""

    def __init__(self, scene, root: str, engine):
        self.scene = scene
        self.engine = engine
        self.name = f"{root}_cmp"
        self.nodes: dict = {}
        self.parts: FigureNodes | None = None
        self._built = None
        self.builds = 0

    def _signature(self, k: float) -> tuple | None:
        c = self.engine.compare
        if c is None:
            return None
        self.place = getattr(self.engine, "compare_place", PLACES[0])  # app.compare_panel's "second body"
        return (id(c), c.shape, id(self.engine.mesh), k, self.place)

    def _clear(self) -> None:
        self.parts = None
        for key in ("root", "first"):  # the root's children go with it
            if key in self.nodes:
                try:
                    self.nodes[key].remove()
                except Exception:
                    pass
        self.nodes = {}

    def _build(self, k: float, size: float) -> None:
        self._clear()
        self.builds += 1  # a fresh name each time: a node removed and added again in one batch kept its old pose
        c, sc, n = self.engine.compare, self.scene, f"{self.name}{self.builds}"
        shape = c.shape
        mesh = self.engine.mesh  # "body drawn as" a mesh: the second body is drawn as the same mesh
        if mesh is not None:
            vertices, faces = mesh.vertices, mesh.faces
        elif shape.kind == "box":
            vertices, faces = box_mesh(shape.dims)
        else:
            vertices, faces = cylinder_mesh(shape.radius, shape.height)
        h = self.nodes
        h["root"] = sc.add_frame(n, show_axes=False, position=OFFSETS[self.place])
        h["body"] = sc.add_frame(f"{n}/body", show_axes=False)
        sc.add_mesh_simple(f"{n}/body/shape", np.asarray(vertices) * k, faces, color=BODY_COLOR, opacity=OPACITY,
                           flat_shading=False)
        self.parts = FigureNodes(sc, f"{n}/body", opacity=PART_OPACITY, scale=PART_SCALE, words=False)
        colors = np.array([_tint(COLORS[x]) for x in ("K", "omega", "axis")], dtype=np.uint8)
        h["arrows"] = sc.add_arrows(f"{n}/arrows", np.zeros((3, 2, 3)), colors, shaft_radius=0.01 * size,
                                    head_radius=0.03 * size, head_length=0.07 * size)
        lift = 0.0 if self.place == "beside" else 0.25 * size  # superimposed: under the first body's label
        h["label"] = sc.add_label(f"{n}/label", f"run 2: {c.diff.label()}", font_screen_scale=0.85,
                                  anchor="bottom-center", position=(0.0, 0.0, -0.75 * size - lift))
        h["first"] = sc.add_label(f"{n}_first", f"run 1: {c.diff.own_label(self.engine.scenario)}",
                                  font_screen_scale=0.85, anchor="bottom-center", position=(0.0, 0.0, -0.75 * size))

    def update(self, k: float, size: float, plots_now: bool) -> None:
        """Inside the session's ``client.atomic()``, after the first body; ``k`` scene units per metre."""
        sig = self._signature(k)
        if sig != self._built:
            self._built = sig
            if sig is None:
                self._clear()
                return
            self._build(k, size)
        if sig is None:
            return
        fr = frame_of(self.engine)
        h = self.nodes
        h["body"].wxyz = fr.body_wxyz
        origin = np.zeros(3)
        h["arrows"].points = np.array([[origin, k * v] for v in (fr.K_vec, fr.omega_vec, fr.axis_vec)])
        self.parts.move(fr.figure, k, size)  # its first frame, or a figure with other names, draws the nodes
        if plots_now:
            status = "" if fr.status == "running" else f" ({fr.status})"
            set_if_changed(h["label"], "text", f"run 2: {self.engine.compare.diff.label()}{status}")
            set_if_changed(h["first"], "text", f"run 1: {self.engine.compare.diff.own_label(self.engine.scenario)}")
