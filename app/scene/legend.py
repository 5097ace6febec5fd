"""The 3-D scene's legend: what each arrow, axis line, trail and internal part is, listing only the parts the
current scene draws (no viser here: the tests read it headless, the panel shows it as markdown). The internal
parts' lines are the system's figure's roles (physics.figure): one line per role, with the role's words, a mark
for the kind of primitive that draws it and its colour.

The colours are the drawing's (``COLORS``, and ``FIGURE_COLORS`` for a figure's colour keys), so a swatch in the
legend is the colour on the canvas.
"""

from __future__ import annotations

import html
import math
from dataclasses import dataclass

import physics

COLORS = {"body": (120, 150, 200), "ellipsoid": (240, 200, 80), "K": (30, 160, 60), "omega": (40, 90, 230),
          "axis": (120, 120, 120), "torque": (220, 60, 200), "trail": (230, 120, 20), "polhode": (150, 40, 200)}
# the shades of physics.figure.COLOURS, the palette a system's primitives name, in its order: a part, an anchor,
# a link, a fluid, a wheel, a marker
SHADES = ((220, 40, 40), (60, 60, 60), (40, 40, 40), (60, 160, 230), (20, 150, 140), (90, 90, 90))
FIGURE_COLORS = dict(zip(physics.figure.COLOURS, SHADES, strict=True))
AXIS_COLORS = ((220, 40, 40), (40, 180, 40), (40, 40, 220))  # viser draws a frame's x, y, z red, green, blue

MARKS = {"arrow": "➜", "line": "━", "ball": "●", "trail": "∿", "solid": "■", "shell": "◯", "disk": "◉",
         "text": "a"}


def mark_of(p) -> str:
    """The legend's mark for a figure primitive: a ball, a see-through ball (a shell), a line, a disk, words."""
    if isinstance(p, physics.figure.Ball):
        return "shell" if p.opacity < 1 else "ball"
    if isinstance(p, physics.figure.Segment):
        return "line"
    return "disk" if isinstance(p, physics.figure.Disk) else "text"


@dataclass(frozen=True)
class Entry:
    """One line of the legend: a part of the scene (``key``), drawn as ``mark`` in ``color``."""

    key: str
    mark: str
    colors: tuple  # one (r, g, b) per mark shown
    text: str


@dataclass(frozen=True)
class SceneParts:
    """What the scene draws now. ``mesh``: the mesh file's name the body is drawn as, or None (the uniform
    solid of its inertia); ``figure``: the internal parts' legend lines, one per role of the system's figure."""

    figure: tuple[Entry, ...] = ()
    braking: bool = False
    polhode: bool = False
    sphere: bool = False  # the momentum sphere beside the body (app.scene.sphere_view)
    view: str = "inertial"
    mesh: str | None = None
    second: str | None = None  # compare mode: what the second (orange) body runs with, e.g. "m = 0 kg"
    symmetric: bool = True  # A = B: e3 is the body's symmetry axis; else only the principal axis of C


SECOND_BODY = ((235, 140, 50),)  # app.scene.compare_view.BODY_COLOR (not imported here: it imports this module)


def parts_of(scenario, *, view: str = "inertial", polhode: bool = False, mesh: str | None = None,
             braking: bool | None = None, sphere: bool = False, second: str | None = None,
             figure: tuple | None = None, state: dict | None = None, **view_values) -> SceneParts:
    """The parts a scenario puts in the scene: its system's figure (``figure`` as drawn, else drawn here from
    ``state``, by default the start of its full model, with the physics.figure.View fields ``view_values``) and
    the braking torque. ``braking``: whether the torque arrow is drawn now (it goes when the body has stopped);
    default b > 0."""
    if braking is None:
        braking = physics.brake_and_medium(scenario)[0] > 0
    if figure is None:
        b = scenario.body
        drawn = physics.figure.View(extent=physics.figure.body_extent(b.A, b.B, b.C, b.M), **view_values)
        figure = physics.get_system(scenario.system).figure(scenario, _start(scenario) if state is None else state,
                                                             drawn)
    return SceneParts(figure=figure_entries(figure), braking=bool(braking), polhode=bool(polhode),
                      sphere=bool(sphere), view=view, mesh=mesh, second=second,
                      symmetric=scenario.body.A == scenario.body.B)


def _start(sc) -> dict[str, float]:
    """Zero for every internal coordinate of the system's full model: the parts as a run that moves them has."""
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    names = model.state_names(len(model.initial_state(sc, p)))
    return dict.fromkeys(names[model.slices(len(names))["internal"]], 0.0)


def figure_entries(figure) -> tuple[Entry, ...]:
    """One legend line per role of a figure, in the figure's order, from the role's first primitive."""
    out: dict[str, Entry] = {}
    for p in figure:
        if p.role and p.role not in out:
            out[p.role] = Entry(p.role, mark_of(p), (FIGURE_COLORS[p.colour],), p.label)
    return tuple(out.values())


def entries(p: SceneParts) -> list[Entry]:
    """The legend's lines for the parts in ``p``, in the order a viewer meets them: arrows, then the body, then
    its parts, then the traces."""
    inertial = p.view != "body"
    out = [Entry("K", "arrow", (COLORS["K"],), "K: angular momentum" + (", fixed (up)" if inertial else "")),
           Entry("omega", "arrow", (COLORS["omega"],), "omega: angular velocity"),
           Entry("e3", "arrow", (COLORS["axis"],), "e3: symmetry axis of the body" if p.symmetric
                 else "e3: principal axis of C (A != B)")]
    if p.braking:
        out.append(Entry("torque", "arrow", (COLORS["torque"],),
                         "control torque: the brake's (against K) or a thruster's"))
    out.append(Entry("merged", "arrow", (COLORS["axis"],), "\"K, omega, e3\": one label for aligned arrows"))
    out.append(Entry("axes", "line", AXIS_COLORS, "thin lines: body axes e1, e2, e3"))
    out.append(Entry("body", "solid", (COLORS["body"],), f"body drawn as {p.mesh} (its inertia: A, B, C)" if p.mesh
                     else "body: uniform solid with its A, B, C"))
    out.append(Entry("ellipsoid", "shell", (COLORS["ellipsoid"],), "inertia ellipsoid (axes 1/sqrt of A, B, C)"))
    if p.second:
        out.append(Entry("second", "solid", SECOND_BODY, f"orange body: the same scene with {p.second} (compare)"))
    out += p.figure
    out.append(Entry("trail", "trail", (COLORS["trail"],), "trail of e3's tip: the nutation cone, last turns"
                     if inertial else "trail of K's direction in the body, last turns"))
    if p.polhode:
        out.append(Entry("polhode", "trail", (COLORS["polhode"],), "polhode: omega's tip on the ellipsoid"))
    if p.sphere:  # its colours: app.scene.sphere_view (not imported here: it imports this module)
        out.append(Entry("sphere", "trail", (COLORS["K"],), "sphere, lower left: K in body axes, its path"))
        out.append(Entry("sphere_curves", "line", ((40, 110, 200), (235, 150, 40), (215, 30, 30), (148, 103, 189)),
                         "on it: curves, separatrix (red), end point"))
    return out


def legend_markdown(p: SceneParts) -> str:
    """The legend for the panel's markdown: one line per part, a coloured mark then the words (as text: a mesh's
    file name is the user's), in one HTML block of the smaller type that fits the longest legend in LEGEND_BOX."""
    lines = ["".join(f"<span style='color:{_hex(c)}'>{MARKS[e.mark]}</span>" for c in e.colors)
             + f" {html.escape(e.text, quote=False)}" for e in entries(p)]
    return f"<div class='{LEGEND_CLASS}' style='{LEGEND_STYLE}'>" + "<br>".join(lines) + "</div>"


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#" + "".join(f"{int(c):02x}" for c in rgb)


# In the panel's own type LEGEND_BOX showed 13 of the 16 lines of a brake, a mass, a cavity, a medium and the sphere
# whole (the trail's was cut, the sphere's two scrolled out of sight, at 1400x900 and 1024x768); in this type all 17
# (with the polhode) show
LEGEND_STYLE = "font-size:12px;line-height:1.3"
LEGEND_CLASS = "quasirigid-legend"
LEGEND_BOX = (12, 160, 330, 330)  # px: x, y, width, height of the floating legend: the 3-D view's left side,
# clear of the body in the middle, of the control panel on the right and of the browser's notices at the top
# left (software WebGL), within a 768 px tall screen, above where tests click to focus the 3-D view (y = 500)
# The window is as tall as its lines (at most LEGEND_BOX's height): at a fixed 330 px the default scene's 14 lines
# left 59 px of empty window under them. Measured in chromium at 1400x900 and 1024x768: a line is 15.6 px
# (12 px at 1.3), the tab bar and padding 65 px (330 px less 17 lines), and the longest line of a preset (the
# brake's, 57 characters with its mark) 289 px of the 291 px the lines have, on one row. A longer line (a mesh's
# file name) counts a row per LEGEND_CHARS characters; where a wider font wraps more, the window scrolls
LEGEND_LINE_PX = 15.6
LEGEND_FRAME_PX = 65.0
LEGEND_CHARS = 58


def legend_height(parts: SceneParts) -> float:
    """The legend window's height (px) for ``parts``: its frame and one row per LEGEND_CHARS characters of each
    line, at most LEGEND_BOX's height (beyond it the window scrolls)."""
    rows = sum(math.ceil((len(e.text) + 1 + len(e.colors)) / LEGEND_CHARS) for e in entries(parts))
    return min(float(LEGEND_BOX[3]), LEGEND_FRAME_PX + rows * LEGEND_LINE_PX)


class LegendView:
    """The legend on the page: a small movable window over the 3-D view (viser's ``add_panel``), or a folder
    of the control panel where a gui has no panels. ``show`` sends the text only when it changed."""

    def __init__(self, gui):
        add_panel = getattr(gui, "add_panel", None)
        if add_panel is not None:
            self.window = add_panel()
            place = self.window.add_tab("Legend")
            x, y, w, h = LEGEND_BOX
            self.window.float(x=x, y=y, width=w, height=h)
        else:
            self.window = None
            place = gui.add_folder("Legend")
        with place:
            self.markdown = gui.add_markdown("")
        self.height = float(LEGEND_BOX[3])

    def show(self, parts: SceneParts) -> None:
        text = legend_markdown(parts)
        if self.markdown.content != text:
            self.markdown.content = text
            height = legend_height(parts)
            if self.window is not None and height != self.height:  # only as the lines change: a user's resize stays
                self.window.set_height(height)
                self.height = height
