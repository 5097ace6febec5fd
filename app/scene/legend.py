"""The 3-D scene's legend: what each arrow, axis line, trail and ball is, listing only the parts the current
scene draws (no viser here: the tests read it headless, the panel shows it as markdown).

The colours are the drawing's (``COLORS``), so a swatch in the legend is the colour on the canvas.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..engine import parts

COLORS = {"body": (120, 150, 200), "ellipsoid": (240, 200, 80), "mass": (220, 40, 40), "rest": (60, 60, 60),
          "spring": (40, 40, 40), "K": (30, 160, 60), "omega": (40, 90, 230), "axis": (120, 120, 120),
          "torque": (220, 60, 200), "trail": (230, 120, 20), "polhode": (150, 40, 200), "bob": (200, 30, 30),
          "arm": (30, 30, 30), "cavity": (60, 160, 230), "mount": (90, 90, 90)}
AXIS_COLORS = ((220, 40, 40), (40, 180, 40), (40, 40, 220))  # viser draws a frame's x, y, z red, green, blue

MARKS = {"arrow": "➜", "line": "━", "ball": "●", "trail": "∿", "solid": "■", "shell": "◯"}


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
    solid of its inertia); ``exaggeration``: the factor the mass's displacement is drawn with."""

    mass: bool = False
    mass_moves: bool = True  # False: the averaged or closed model, which has no displacement to draw
    exaggeration: float = 1.0
    cavity: bool = False
    bobs: int = 0
    spherical: bool = False
    braking: bool = False
    polhode: bool = False
    sphere: bool = False  # the momentum sphere beside the body (app.scene.sphere_view)
    view: str = "inertial"
    mesh: str | None = None
    second: str | None = None  # compare mode: what the second (orange) body runs with, e.g. "m = 0 kg"


SECOND_BODY = ((235, 140, 50),)  # app.scene.compare_view.BODY_COLOR (not imported here: it imports this module)


def parts_of(scenario, *, view: str = "inertial", polhode: bool = False, mesh: str | None = None,
             exaggeration: float = 1.0, mass_moves: bool = True, braking: bool | None = None,
             sphere: bool = False, second: str | None = None) -> SceneParts:
    """The parts a scenario puts in the scene (physics.Scenario: mass, cavity, pendulums, braking b).
    ``braking``: whether the torque arrow is drawn now (it goes when the body has stopped); default b > 0."""
    if braking is None:
        control = getattr(scenario, "control", None)
        braking = control is not None and float(getattr(control, "b", 0.0)) > 0
    return SceneParts(mass=scenario.mass is not None, mass_moves=mass_moves, exaggeration=float(exaggeration),
                      cavity=scenario.cavity is not None,
                      bobs=parts.bob_count(scenario),
                      spherical=scenario.pendulum is not None, braking=bool(braking),
                      polhode=bool(polhode), sphere=bool(sphere), view=view, mesh=mesh, second=second)


def entries(p: SceneParts) -> list[Entry]:
    """The legend's lines for the parts in ``p``, in the order a viewer meets them: arrows, then the body, then
    its parts, then the traces."""
    inertial = p.view != "body"
    out = [Entry("K", "arrow", (COLORS["K"],), "K: angular momentum" + (", fixed (up)" if inertial else "")),
           Entry("omega", "arrow", (COLORS["omega"],), "omega: angular velocity"),
           Entry("e3", "arrow", (COLORS["axis"],), "e3: symmetry axis of the body")]
    if p.braking:
        out.append(Entry("torque", "arrow", (COLORS["torque"],), "braking torque (against K)"))
    out.append(Entry("merged", "arrow", (COLORS["axis"],), "\"K, omega, e3\": one label for aligned arrows"))
    out.append(Entry("axes", "line", AXIS_COLORS, "thin lines: body axes e1, e2, e3"))
    out.append(Entry("body", "solid", (COLORS["body"],), f"body drawn as {p.mesh} (its inertia: A, B, C)" if p.mesh
                     else "body: uniform solid with its A, B, C"))
    out.append(Entry("ellipsoid", "shell", (COLORS["ellipsoid"],), "inertia ellipsoid (axes 1/sqrt of A, B, C)"))
    if p.second:
        out.append(Entry("second", "solid", SECOND_BODY, f"orange body: the same scene with {p.second} (compare)"))
    if p.cavity:
        out.append(Entry("cavity", "shell", (COLORS["cavity"],), "cavity filled with viscous fluid"))
    if p.mass:
        if p.mass_moves:
            out.append(Entry("mass", "ball", (COLORS["mass"],), f"moving mass m; its displacement u drawn "
                             f"x {p.exaggeration:g}"))
            out.append(Entry("spring", "line", (COLORS["spring"],), "spring: rest point to mass"))
        else:
            out.append(Entry("mass", "ball", (COLORS["mass"],), "moving mass m, at rest (this fidelity averages "
                             "its motion)"))
        out.append(Entry("rest", "ball", (COLORS["rest"],), "rest point O1, on e3 at rho"))
        out.append(Entry("mount", "line", (COLORS["mount"],), "mount: O1 is fixed to the body"))
    if p.bobs:
        what = "spherical pendulum bob" if p.spherical and p.bobs == 1 else "pendulum bob"
        out.append(Entry("bob", "ball", (COLORS["bob"],), f"{what}{'s' if p.bobs > 1 else ''} ({p.bobs}) "
                         f"on {'its arm' if p.bobs == 1 else 'their arms'}"))
    out.append(Entry("trail", "trail", (COLORS["trail"],), "trail of e3's tip: the nutation cone, last turns"
                     if inertial else "trail of K's direction in the body, last turns"))
    if p.polhode:
        out.append(Entry("polhode", "trail", (COLORS["polhode"],), "polhode: omega's tip on the ellipsoid"))
    if p.sphere:  # its colours: app.scene.sphere_view (not imported here: it imports this module)
        out.append(Entry("sphere", "trail", (COLORS["K"],), "sphere, lower left: K in body axes, its path"))
        out.append(Entry("sphere_curves", "line", ((40, 110, 200), (235, 150, 40), (215, 30, 30)),
                         "on it: energy curves; separatrix (red)"))
    return out


def legend_markdown(p: SceneParts) -> str:
    """The legend as markdown: one line per part, a coloured mark then the words."""
    lines = ["".join(f"<span style='color:{_hex(c)}'>{MARKS[e.mark]}</span>" for c in e.colors) + f" {e.text}"
             for e in entries(p)]
    return "  \n".join(lines)


def _hex(rgb: tuple[int, int, int]) -> str:
    return "#" + "".join(f"{int(c):02x}" for c in rgb)


LEGEND_BOX = (12, 160, 330, 330)  # px: x, y, width, height of the floating legend: the 3-D view's left side,
# clear of the body in the middle, of the control panel on the right and of the browser's notices at the top
# left (software WebGL), within a 768 px tall screen, above where tests click to focus the 3-D view (y = 500)


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

    def show(self, parts: SceneParts) -> None:
        text = legend_markdown(parts)
        if self.markdown.content != text:
            self.markdown.content = text
