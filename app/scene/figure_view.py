"""A system's figure (physics.figure primitives, body frame, metres) as viser scene nodes, one node per
primitive name under a parent frame: a ball is an icosphere, a segment line segments, a disk a translucent
face with its rim and SPOKES radii marking its angle (a turning wheel is seen to turn), words a label. ``draw``
makes the nodes (again where a primitive's look changed, none for a name gone); ``move`` sets where the moving
ones are now. Names no system.
"""

from __future__ import annotations

import numpy as np

import physics

from .legend import FIGURE_COLORS

fig = physics.figure
DISK_SIDES = 48  # the circle a disk is drawn as
SPOKES = 3  # radii drawn on a disk: one alone read as a line through the body's axes in the screenshots
DISK_LINE = 0.012  # a disk's rim and spokes, x the body's drawn size: 0.006 was a hairline over the body
DISK_FACE_OPACITY = 0.35  # the face is translucent, so the body's axes and the arrows show through it


def _look(p) -> tuple:
    """What a node is made with (a change makes it again); where it is goes to ``move``."""
    if isinstance(p, fig.Ball):
        return ("ball", p.colour, p.opacity, p.radius, p.size)
    if isinstance(p, fig.Segment):
        return ("segment", p.colour, p.opacity, p.thickness)
    if isinstance(p, fig.Disk):
        return ("disk", p.colour, p.opacity, p.size, p.centre, p.normal, p.radius)  # the face is made where it is
    return ("text", p.colour)


def _disk_frame(p, k: float, size: float):
    """(centre, e, f, r) of a disk in scene units: e the reference direction, f = normal x e, r its radius."""
    n, e = np.array(p.normal), np.array(p.ref)
    return np.array(p.centre) * k, e, np.cross(n, e), max(p.radius * k, p.size * size)


def disk_segments(p, k: float, size: float) -> np.ndarray:
    """(DISK_SIDES + SPOKES, 2, 3) scene units: the disk's rim, and SPOKES radii evenly spaced from its angle."""
    c, e, f, r = _disk_frame(p, k, size)
    a = np.linspace(0.0, 2 * np.pi, DISK_SIDES + 1)
    rim = c + r * (np.cos(a)[:, None] * e + np.sin(a)[:, None] * f)
    b = p.angle + 2 * np.pi * np.arange(SPOKES) / SPOKES
    tips = c + r * (np.cos(b)[:, None] * e + np.sin(b)[:, None] * f)
    spokes = np.stack([np.broadcast_to(c, tips.shape), tips], axis=1)
    return np.concatenate([np.stack([rim[:-1], rim[1:]], axis=1), spokes])


def disk_face(p, k: float, size: float) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of the disk's face, a fan from its centre, scene units (it looks the same at any angle,
    so it is made once and only the spokes turn)."""
    c, e, f, r = _disk_frame(p, k, size)
    a = np.linspace(0.0, 2 * np.pi, DISK_SIDES, endpoint=False)
    vertices = np.vstack([c, c + r * (np.cos(a)[:, None] * e + np.sin(a)[:, None] * f)])
    i = np.arange(DISK_SIDES)
    faces = np.column_stack([np.zeros(DISK_SIDES, dtype=np.int64), 1 + i, 1 + (i + 1) % DISK_SIDES])
    return vertices, faces


class FigureNodes:
    """The nodes of one figure under ``parent`` (a frame's name). ``opacity`` and ``scale`` dim and shrink every
    part (compare mode's second body); ``words``: draw the figure's Text (the second body leaves them out)."""

    def __init__(self, scene, parent: str, opacity: float = 1.0, scale: float = 1.0, words: bool = True):
        self.scene, self.parent = scene, parent
        self.opacity, self.scale, self.words = opacity, scale, words
        self.nodes: dict = {}
        self.looks: dict = {}

    def forget(self) -> None:
        """Drop the nodes without removing them: their parent went, and they with it."""
        self.nodes, self.looks = {}, {}

    def draw(self, figure, k: float, size: float) -> None:
        """Nodes for ``figure`` at ``k`` scene units per metre on a body drawn ``size`` units across: the ones whose
        look changed made again, the ones whose name is gone removed."""
        shown = {p.name: p for p in figure if self.words or not isinstance(p, fig.Text)}
        for name in [n for n in self.nodes if n not in shown or self.looks[n] != (_look(shown[n]), k)]:
            try:
                self.nodes.pop(name).remove()
            except Exception:
                pass
            del self.looks[name]
        for name, p in shown.items():
            if name not in self.nodes:
                self.nodes[name] = self._add(p, k, size)
                self.looks[name] = (_look(p), k)
        self.move(figure, k, size, every=True)

    def _add(self, p, k: float, size: float):
        sc, path = self.scene, f"{self.parent}/fig_{p.name}"
        color = FIGURE_COLORS[p.colour]
        opacity = p.opacity * self.opacity
        see = {"opacity": opacity} if opacity < 1 else {}
        if isinstance(p, fig.Ball):
            radius = max(p.radius * k, p.size * size) * self.scale
            return sc.add_icosphere(path, radius=radius, color=color, position=tuple(k * np.array(p.centre)), **see)
        if isinstance(p, fig.Segment):
            thickness = p.thickness * size * self.scale
            return sc.add_line_segments(path, k * np.array([[p.a, p.b]]), color, thickness=thickness)
        if isinstance(p, fig.Disk):
            node = sc.add_line_segments(path, disk_segments(p, k, size), color, thickness=DISK_LINE * size)
            vertices, faces = disk_face(p, k, size)  # a child: removed with its rim
            sc.add_mesh_simple(f"{path}/face", vertices, faces, color=color, opacity=DISK_FACE_OPACITY * opacity,
                               side="double", cast_shadow=False)
            return node
        return sc.add_label(path, p.text, position=tuple(k * np.array(p.position)))

    def move(self, figure, k: float, size: float, every: bool = False) -> None:
        """Where the moving primitives are now (``every``: the static ones too, just made); a figure with other
        names than the nodes (a model that draws another set of parts) is drawn again."""
        if not every and {p.name for p in figure if self.words or not isinstance(p, fig.Text)} != set(self.nodes):
            self.draw(figure, k, size)
            return
        for p in figure:
            h = self.nodes.get(p.name)
            if h is None or not (p.moves or every):
                continue
            if isinstance(p, fig.Ball):
                h.position = tuple(k * np.array(p.centre))
            elif isinstance(p, fig.Segment):
                h.points = k * np.array([[p.a, p.b]])
            elif isinstance(p, fig.Disk):
                if self.looks[p.name] != (_look(p), k):  # moved or turned over: its face is made again
                    self.draw(figure, k, size)
                    return
                h.points = disk_segments(p, k, size)
            else:
                h.position = tuple(k * np.array(p.position))
                if h.text != p.text:
                    h.text = p.text
