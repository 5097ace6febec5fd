"""One tab's view of the class run (app.serve.classroom): what the lecturer's and each student's tab draw from the
one class engine.

``Drawing.update`` and ``Panel.update`` clear the engine's change flags (``scene_changed``, ``sliders_changed``,
``plots_changed``) once they have drawn a change, which only one view could do. So each view reads the engine
through an ``EngineView``: every attribute and method is the engine's, except the three flags, which are the
view's own; the class loop raises them on every view when the engine raised them (``Shared.take_flags``). What
every view reads out of one frame (the plots' arrays from t = 0, the readouts, the details) is computed once per
frame and shared (``Shared``), so a following tab costs only its drawing and its messages.

The class's 3-D scene is drawn once, in viser's scene shared by every tab (``server.scene``): ``ClassDrawing`` is
the explorer's ``Drawing`` on that scene, whose messages viser sends to every tab, so a following tab costs no
Python for its scene. Each tab keeps its own legend (a panel of its own; the class drawing says what it shows,
``legend_parts``) and its own panel. A tab whose student explores a run of their own hides the class's scene in that
tab alone (``show_class_scene``).

``FollowerPanel`` is a student's panel: the status ("following the class"), "Explore from here", the readouts,
the Details and the plots; no control of the class run.
"""

from __future__ import annotations

import viser

from ..engine.compare import readout_md as compare_readout_md
from ..engine.engine import Engine
from ..handles import set_if_changed
from ..panel import plots
from ..panel.compare_plots import ComparePlots
from ..panel.energy_plot import EnergyChart
from ..panel.panel import Panel, _details_md, _readout_md
from ..scene import camera
from ..scene.drawing import Drawing
from ..scene.legend import LegendView
from .message_guard import screen_gui_updates
from .upload_cap import cap_streamed_uploads

FLAGS = ("scene_changed", "sliders_changed", "plots_changed")
# The class drawing's root is /sclass/all (a tab's own is /s<client id>: app.scene.drawing). Drawing names its light,
# grid, momentum sphere and compare mode's second body as siblings of its root (root_fill, root_sphere,
# root_cmp3...), so all of them sit under /sclass, a frame ClassDrawing makes first: hiding that one node hides the
# whole class scene in a tab, the nodes made after the hiding too (a new race's second body).
CLASS_ID = "class/all"
CLASS_NODES = ("/sclass",)


class Shared:
    """What every view of one frame reads: computed on first use in the frame, then the same for all."""

    def __init__(self, engine: Engine):
        self.engine = engine
        self.frame = 0
        self._cache: dict = {}
        self.flags = dict.fromkeys(FLAGS, False)

    def take_flags(self) -> None:
        """A new frame: the engine's change flags, raised since the last one, become every view's (which each clears
        once drawn); the engine's are cleared here, so the views never race one another for them."""
        eng = self.engine
        self.frame += 1
        self._cache.clear()
        for name in FLAGS:
            self.flags[name] = bool(getattr(eng, name))
            setattr(eng, name, False)

    def get(self, name: str, compute):
        if name not in self._cache:
            self._cache[name] = compute()
        return self._cache[name]


class EngineView:
    """The class engine as one view sees it: its own change flags, the frame's shared outputs, the rest the
    engine's (reads and writes: a lecturer's panel sets ``error`` on the engine itself)."""

    def __init__(self, engine: Engine, shared: Shared):
        object.__setattr__(self, "_engine", engine)
        object.__setattr__(self, "_shared", shared)
        for name in FLAGS:
            object.__setattr__(self, name, True)  # a new view draws everything once

    def raise_flags(self) -> None:
        for name, up in self._shared.flags.items():
            if up:
                object.__setattr__(self, name, True)

    def __getattr__(self, name: str):
        return getattr(self._engine, name)

    def __setattr__(self, name: str, value) -> None:
        if name in FLAGS:
            object.__setattr__(self, name, value)
        else:
            setattr(self._engine, name, value)

    def plot_data(self, span: str | None = None):
        if span is not None:
            return self._engine.plot_data(span)
        return self._shared.get("plot_data", self._engine.plot_data)

    def readouts(self) -> dict[str, str]:
        return self._shared.get("readouts", self._engine.readouts)

    def details(self) -> dict[str, str]:
        return self._shared.get("details", self._engine.details)

    def end_state(self, block: bool = False):
        # the engine's asks the run for K (its invariants) each time: once a frame, not once a tab
        return self._engine.end_state(True) if block else self._shared.get("end_state", self._engine.end_state)

    def once_per_frame(self, name: str, compute):
        return self._shared.get(name, compute)


class FollowerPanel:
    """A student's panel while following: what the class run shows, and the way to a run of one's own."""

    def __init__(self, client: viser.ClientHandle, view: EngineView, on_explore):
        gui = self.gui = client.gui
        self.view = view
        gui.configure_theme(control_width="large")
        self.status_md = gui.add_markdown("**Quasirigid class** · following the class")
        self.explore = gui.add_button("Explore from here", hint="a run of your own from the class run's present "
                                      "state and scene, with every control; \"Follow the class\" comes back")
        self.explore.on_click(lambda _event: on_explore())
        self.readout_md = gui.add_markdown("")
        self.compare_md = gui.add_markdown("")
        with gui.add_folder("Details", expand_by_default=False):
            self.details_md = gui.add_markdown("")
        data = view.plot_data()
        with gui.add_folder("Plots"):
            self.plots = plots.build_plots(gui, data)
            self.plots.span.visible = False  # the lecturer's choice of span is what the class sees
            self.compare_plots = ComparePlots(gui, data)
            b = view.scenario.body
            self.energy = EnergyChart(gui, data, (b.A, b.B, b.C), visible=view.show_sphere)

    def update(self, fr, plots_now: bool, lecturer_here: bool) -> None:
        eng = self.view
        eng.sliders_changed = False  # no sliders here
        if plots_now:
            self.energy.update(eng, changed=eng.plots_changed)
        if plots_now and eng.plots_changed:
            eng.plots_changed = False
            if not self.compare_plots.update(eng, self.plots):
                plots.update_plots(self.plots, eng.plot_data(), eng.has_overlay, eng.overlay_title())
            self.readout_md.content = _readout_md(eng)
            set_if_changed(self.compare_md, "content", compare_readout_md(eng))
            set_if_changed(self.details_md, "content", _details_md(eng))
        state = "playing" if eng.playing else "paused"
        if fr.status != "running":
            state = fr.status
        away = "" if lecturer_here else " · the lecturer's tab is closed"
        set_if_changed(self.status_md, "content", f"**Quasirigid class** · following the class · {state} · "
                       f"warp {eng.warp:.3g}x{away}")


class _Camera:
    """The shared scene has no camera of its own: each tab's is set when it joins (``place_camera``)."""

    position = look_at = None


class _Legend:
    """The class drawing's legend: what it would show, kept for every tab's own legend."""

    parts = None

    def show(self, parts) -> None:
        self.parts = parts


class _Everyone:
    """What ``Drawing`` needs of a client, for the scene every tab shares."""

    client_id = CLASS_ID

    def __init__(self, server: viser.ViserServer):
        self.scene = server.scene
        self.camera = _Camera()
        self.gui = None


class ClassDrawing(Drawing):
    """The explorer's Drawing of the class run in viser's shared scene (``server.scene``): drawn once a frame
    for every tab; its legend is handed to each tab's own (``legend_parts``)."""

    def __init__(self, server: viser.ViserServer, view: EngineView):
        self.client = _Everyone(server)
        self.engine = view
        self.legend = _Legend()
        # the parent of every class node, made here as a real frame: an ancestor viser makes on its own is a
        # "virtual anchor", which a tab's visibility update does not hide
        self.parent = server.scene.add_frame(CLASS_NODES[0], show_axes=False)
        self._build_scene()

    @property
    def legend_parts(self):
        return self.legend.parts


def place_camera(client: viser.ClientHandle) -> None:
    """A joining tab's view, as a tab of its own starts (app.scene.camera)."""
    camera.place(client.camera)
    camera.fit_when_known(client.camera)


def show_class_scene(client: viser.ClientHandle, shown: bool) -> None:
    """Show or hide the class's scene in this tab alone (a student exploring a run of their own draws theirs): the
    message a node's ``visible`` sends (SetSceneNodeVisibilityMessage; a SceneNodeUpdateMessage of "visible", sent
    before, left the class's body drawn over the student's), for the broadcast variant of the shared nodes, sent to
    this tab's connection only."""
    from viser import _messages

    for name in CLASS_NODES:
        client._websock_connection.queue_message(_messages.SetSceneNodeVisibilityMessage(name=name, visible=shown))


class FollowerView:
    """A student's tab following the class: the shared scene, its own legend and a read-only panel."""

    role = "student"

    def __init__(self, client: viser.ClientHandle, engine: Engine, shared: Shared, drawing: ClassDrawing,
                 on_explore):
        self.client = client
        self.view = EngineView(engine, shared)
        self.drawing = drawing
        self.panel = FollowerPanel(client, self.view, on_explore)
        self.legend = LegendView(client.gui)
        place_camera(client)
        self.published = 0

    def publish(self, fr, plots_now: bool, lecturer_here: bool) -> None:
        self.view.raise_flags()
        if plots_now:
            with self.client.atomic():
                self.panel.update(fr, plots_now, lecturer_here)
                if self.drawing.legend_parts is not None:
                    self.legend.show(self.drawing.legend_parts)
        else:  # the status line at most: no bundle of messages to open and close for it
            self.panel.update(fr, plots_now, lecturer_here)
        self.published += 1


class LecturerView:
    """The lecturer's tab: the explorer's whole panel over an EngineView of the class engine, and the shared
    scene; its callbacks queue requests on the class engine, which the class loop applies."""

    role = "lecturer"

    def __init__(self, client: viser.ClientHandle, engine: Engine, shared: Shared, drawing: ClassDrawing,
                 klass=None):
        self.client = client
        self.view = EngineView(engine, shared)
        self.drawing = drawing
        # a lecturer's reload never resets the class; klass: the class's challenge, its start and scores
        self.panel = Panel(client, self.view, restore=False, still=False, klass=klass)
        self.legend = LegendView(client.gui)
        cap_streamed_uploads(client.gui, self._refuse)
        screen_gui_updates(client.gui, self._refuse)
        place_camera(client)
        self.published = 0

    def _refuse(self, message: str) -> None:
        self.view.error = message

    def publish(self, fr, plots_now: bool, lecturer_here: bool) -> None:
        self.view.raise_flags()
        with self.client.atomic():
            self.panel.update(fr, plots_now)
            if plots_now and self.drawing.legend_parts is not None:
                self.legend.show(self.drawing.legend_parts)
        self.published += 1


def waiting_note(client: viser.ClientHandle):
    """What a student's tab shows before the lecturer has opened the class."""
    return client.gui.add_markdown("**Quasirigid class** · waiting for the lecturer: this page follows the class "
                                   "run as soon as the lecturer opens it")


__all__ = ["CLASS_NODES", "ClassDrawing", "EngineView", "FollowerPanel", "FollowerView", "LecturerView", "Shared",
           "show_class_scene", "waiting_note"]
