"""One tab's control panel: the status line, readouts, plots, playback, model, sliders, view, file and
the lazily built study panels. Callbacks only record requests on the engine; ``update`` shows a frame's
numbers and ``sync`` pushes slider values and ranges after a scene change.
"""

from __future__ import annotations

import numpy as np
import viser

import physics

from ..engine import controls, edits, presets, words
from ..engine.actions import system_actions
from ..engine.compare import readout_md as compare_readout_md
from ..engine.engine import Engine
from ..engine.mesh import INERTIA_SHAPE, asset_names
from ..engine.workers import OVERLAYS
from ..handles import set_if_changed
from ..markup import plain
from ..replay.export import ReplayButton
from ..share.panel import SharePanel
from . import plots
from .challenge_panel import ChallengePanel, ClassChallenge
from .compare_panel import ComparePanel
from .compare_plots import ComparePlots
from .control_notes import NotePlace
from .energy_plot import EnergyChart
from .motion import ReducedMotion
from .playbar import Playbar
from .typed_numbers import TypedNumbers

EDITED = " (edited)"  # the preset dropdown's name for a preset changed since it was loaded
ALL = "all"  # an item action's first option: the sliders edit every item


class Panel:
    """The GUI of one browser tab."""

    def __init__(self, client: viser.ClientHandle, engine: Engine, restore: bool = True, still: bool = True,
                 klass: ClassChallenge | None = None):
        self.client = client
        self.engine = engine
        self.klass = klass  # class mode's side of the braking challenge (app.serve.scoreboard), or None
        self.restore = restore  # whether the browser's last scene may replace the one the tab starts with
        self._build_gui()
        # a tab that runs its own scene from the start (not one carried on from the class's) honours the browser's
        # reduced-motion setting
        self.motion = ReducedMotion(client, engine, read=still)

    def __getattr__(self, name: str):
        """A system's action's widget by the action's name (``panel.pivot``): the names come from physics."""
        widgets = self.__dict__.get("action_widgets", {})
        if name in widgets:
            return widgets[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _add_actions(self, folder: str) -> None:
        """The widgets of every system's actions (physics.figure.Action) that sit in ``folder``, one per name;
        shown for a scene whose system has the action and what it acts on (``sync``)."""
        gui, eng = self.client.gui, self.engine
        for a in system_actions(None):
            if a.folder != folder or a.name in self.action_widgets:
                continue
            if a.kind == "button":
                h = gui.add_button(a.label, hint=a.hint)
            elif a.kind == "choice":
                h = gui.add_dropdown(a.label, list(a.options), initial_value=eng.choices.get(a.key, a.options[0]),
                                     hint=a.hint)
            elif a.kind == "item":
                h = gui.add_dropdown(a.label, [ALL, *a.options_of(eng.scenario)], initial_value=ALL, hint=a.hint)
            else:
                h = gui.add_slider(a.label, min=a.lo, max=a.hi, step=a.step or (a.hi - a.lo) / 100,
                                   initial_value=float(min(max(getattr(eng, a.key), a.lo), a.hi)), hint=a.hint)
            self.action_widgets[a.name] = h

    def _build_gui(self) -> None:
        gui, eng = self.client.gui, self.engine
        gui.configure_theme(control_width="large", show_share_button=False)  # app.serve.guard.refuse_share_tunnel
        # The Run row first: the status line below it grows and shrinks as it plays ("reaching N x" comes and goes
        # with the machine's pace), and a row under it jumped as the pointer reached for Pause.
        self.playbar = Playbar(gui, eng)
        self.status_md = gui.add_markdown("**Quasirigid explorer**")
        self.readout_md = gui.add_markdown("")
        self.compare_md = gui.add_markdown("")  # compare mode: both runs' theta, |K| and E (app.engine.compare)
        self.error_md = gui.add_markdown("")
        with gui.add_folder("Details", expand_by_default=False):  # the technical side, one click away
            self.details_md = gui.add_markdown("")
        with gui.add_folder("Plots"):
            self.plots = plots.build_plots(gui, eng.plot_data())
            self.compare_plots = ComparePlots(gui, eng.plot_data())  # both runs overlaid, in compare mode
            self.energy = EnergyChart(gui, eng.plot_data(), (eng.scenario.body.A, eng.scenario.body.B,
                                                             eng.scenario.body.C), visible=eng.show_sphere)
        with gui.add_folder("Playback"):
            self.warp = gui.add_slider("time warp (log10 x)", min=-1.0, max=4.0, step=0.05,
                                       initial_value=float(np.log10(eng.warp)),
                                       hint="simulated seconds per wall second, as a power of ten (0 = 1x, 3 = 1000x)")
            self.restart = gui.add_checkbox("restart on change", False,
                                            hint="restart from t = 0 on every change, instead of going on "
                                            "with the angular momentum K and the attitude kept")
        with gui.add_folder("Model"):
            self.preset_names = presets.preset_names()
            self.preset = gui.add_dropdown("Preset", self.preset_names, initial_value=presets.DEFAULT,
                                           hint="choosing a preset again reloads it")
            self.system = gui.add_dropdown("System", list(controls.SYSTEM_LABELS),
                                           initial_value=_system_label(eng.scenario.system))
            self.fidelity = gui.add_dropdown("Fidelity", list(controls.FIDELITIES), initial_value=eng.fidelity_choice,
                                             hint="full multibody, averaged (quasi-rigid), closed form, or auto")
            self.accuracy = gui.add_dropdown("auto's accuracy", list(controls.accuracy_options(eng.accuracy_choice)),
                                             initial_value=controls.accuracy_label(eng.accuracy_choice),
                                             visible=eng.fidelity_choice == "auto",
                                             hint="auto runs the cheapest model whose error estimate on theta, "
                                             "over the run, is at most this (run.accuracy)")
            self.badge_md = gui.add_markdown("")
            self.overlay = gui.add_dropdown("Overlay prediction", list(OVERLAYS),
                                            initial_value="none",
                                            hint="a cheaper fidelity's theta(t), computed with physics.simulate")
            self.action_widgets: dict = {}
            self._add_actions("Model")
        self.panels: dict = {}
        self._panels_scene = None  # the scenario the study panels last judged their results against
        self.sliders, self.folders = _build_sliders(gui, eng.values)
        folder_of = {key: self.folders[title] for title, keys in controls.FOLDERS for key in keys}
        self.notes = NotePlace(gui, self.sliders, folder_of, self.error_md.order,
                               undo=lambda: eng.request("undo"), reset=lambda: eng.request("reload"))
        for title, folder in self.folders.items():
            with folder:
                self._add_actions(title)
        start = next(p.folder for p in controls.PARAMS if p.base and p.restarts)  # the Initial state folder
        with self.folders[start]:
            self.start_md = gui.add_markdown("")  # the theta(0) the run starts from, when not the slider's
        with gui.add_folder("View"):
            self.view = gui.add_dropdown("Frame", ["inertial", "body"], initial_value="inertial",
                                         hint="inertial: K fixed and pointing up; body: the body stays still")
            self._add_actions("View")
            self.polhode = gui.add_checkbox("polhode", False, hint="the tip of omega on the inertia ellipsoid, in "
                                            "the body (Poinsot): closed loops when nothing dissipates")
            self.sphere = gui.add_checkbox("momentum sphere", eng.show_sphere,
                                           hint="lower left of the 3-D view: K's direction in body axes on the "
                                           "sphere |K| = const, the polhodes (blue about the axis of largest "
                                           "moment), the separatrix (red) and K's path; with a chart of E and the "
                                           "pure spins")
            self.body_mesh = gui.add_dropdown("body drawn as", [INERTIA_SHAPE, *asset_names()],
                                              initial_value=INERTIA_SHAPE,
                                              hint="a mesh from assets/meshes: its inertia ratios replace A, B, C "
                                              "(scaled to keep A + B + C); restarts the run")
        for title in dict.fromkeys(a.folder for a in system_actions(None) if a.name not in self.action_widgets):
            with gui.add_folder(title):  # an action in a folder the panel does not have: a folder of its own
                self._add_actions(title)
        self.compare = ComparePanel(gui, eng)  # the Compare folder: a second run with one difference
        self.challenge = ChallengePanel(gui, eng, self.klass)  # the braking challenge: thrusters vs the optimal law
        with gui.add_folder("File", expand_by_default=False):
            self.toml_btn = gui.add_button("Download scenario (TOML)")
            self.csv_btn = gui.add_button("Download trajectory (CSV)")
            self.upload = gui.add_upload_button("Load scenario (TOML)", mime_type=".toml",
                                                hint="a scenario file, as `python -m physics` reads (64 kB at most)")
            self.upload_md = gui.add_markdown("")  # what came of an upload, under its button (engine.upload_note)
            self.replay = ReplayButton(gui, eng, self.client)  # the scene as an offline HTML replay (app.replay.export)
        self.share = SharePanel(gui, eng, self.client, restore=self.restore)  # code, link, last scene (share_panel)
        self._lazy_panel("Speed vs accuracy", "speed_panel", "SpeedPanel",
                         lambda sc: eng.request("scenario", (sc, f"{eng.preset} (recommended method)")))
        self._lazy_panel("Sweep", "sweep_panel", "SweepPanel",
                         lambda sc: eng.request("scenario", (sc, "sweep point")), scene=self.client.scene)
        self._lazy_panel("Design", "design_panel", "DesignPanel",
                         lambda sc: eng.request("scenario", (sc, "design")),
                         compare=lambda spec: eng.request("compare", spec))

        def on(handle, action, convert=lambda v: v):
            # async, so viser runs it on its event loop right where it stores the client's value. A plain callback
            # runs later on a pool thread, and by then the frame loop may have set the control back to the
            # engine's value (_sync_choices, every frame): the old value was read and the choice lost.
            @handle.on_update
            async def _(event):
                if event.client is None:  # our own assignment of a value: not a user's change
                    return
                try:  # a raw client can send anything: a bad value is said, never a traceback
                    value = convert(handle.value)
                except (TypeError, ValueError, OverflowError, KeyError) as exc:
                    eng.error = f"{handle.label}: {str(handle.value)[:40]!r} is not allowed ({type(exc).__name__})"
                    return
                eng.request(action, value)

        def click(handle, action):
            @handle.on_click
            def _(_event):
                eng.request(action)

        for a in system_actions(None):
            h = self.action_widgets[a.name]
            if a.kind == "button":
                click(h, a.name)
            elif a.kind == "item":
                on(h, a.name, lambda v, a=a: None if v == ALL else list(a.options_of(eng.scenario)).index(v))
            else:
                on(h, a.name)
        on(self.warp, "warp", lambda v: 10.0 ** float(v))
        on(self.restart, "restart_on_change")

        @self.preset.on_update
        async def _(event):  # read as it arrives, as on() does: _sync_preset sets the dropdown every frame
            # the scene's own name ("... (edited)", an upload) is not a preset to load
            if event.client is not None and self.preset.value in self.preset_names:
                eng.request("preset", self.preset.value)

        on(self.system, "system", lambda v: controls.SYSTEM_LABELS[v])
        on(self.fidelity, "fidelity")
        on(self.accuracy, "accuracy", lambda v: controls.accuracy_options(eng.accuracy_choice)[v])
        on(self.overlay, "overlay")
        on(self.plots.span, "plots", lambda v: plots.SPANS[v])
        on(self.view, "view")
        on(self.polhode, "polhode")
        on(self.sphere, "sphere")
        on(self.body_mesh, "mesh")
        for key, slider in self.sliders.items():
            self._bind_slider(key, slider)

        @self.toml_btn.on_click
        def _(event):
            (event.client or self.client).send_file_download("scenario.toml", eng.toml(), save_immediately=True)

        @self.csv_btn.on_click
        def _(event):
            (event.client or self.client).send_file_download("trajectory.csv", eng.csv(), save_immediately=True)

        @self.upload.on_upload
        def _(_event):
            f = self.upload.value
            eng.request("upload", (f.name, f.content))

        others = [(self.warp, lambda v: eng.request("warp", 10.0 ** v))]  # the sliders that are no parameter
        others += [(self.action_widgets[a.name], lambda v, a=a: eng.request(a.name, v))
                   for a in system_actions(None) if a.kind not in ("button", "choice", "item")]
        self.typed = TypedNumbers(gui, self.sliders, eng, others)  # what is typed in a slider's box, read here

    def _lazy_panel(self, title: str, module: str, cls: str, apply, **options) -> None:
        """A folder whose panel is built on first open: panels pull in plotly (and its script in the
        browser), which the first frame should not wait for."""
        gui = self.client.gui
        with gui.add_folder(title, expand_by_default=False) as folder:
            opener = gui.add_button(f"Open the {title.lower()} panel")

        @opener.on_click
        def _(_event):
            import importlib

            try:
                panel_class = getattr(importlib.import_module(f"..studies.{module}", __package__), cls)
                with folder:
                    self.panels[title] = panel_class(gui, lambda: self.engine.scenario, apply, **options)
                opener.remove()
            except Exception as exc:  # a panel that cannot open says so; the tab runs on
                self.engine.error = f"{title} panel: {type(exc).__name__}: {exc}"

    def _bind_slider(self, key: str, slider) -> None:
        @slider.on_update
        async def _(event):  # read as it arrives, as on() does: a revert or a new scene sets sliders from the loop
            if event.client is None:
                return
            self.engine.request_value(key, float(slider.value))

    def sync(self) -> None:
        """After a preset or system change: slider values, ranges and which folders apply."""
        eng = self.engine
        system = eng.scenario.system
        for key, slider in self.sliders.items():  # assign only what differs: each assignment is a message
            p = controls.BY_KEY[key]
            lo, hi = controls.slider_range(p, eng.values[key])
            set_if_changed(slider, "min", lo)
            set_if_changed(slider, "max", hi)
            set_if_changed(slider, "precision", _digits(p.step, lo, hi, eng.values[key]))  # the box shows the value
            set_if_changed(slider, "value", min(max(eng.values[key], lo), hi))
            set_if_changed(slider, "disabled", system not in p.systems)
        shown = controls.folders_of(system)  # the body's, the start's and the system's own
        for title, folder in self.folders.items():
            set_if_changed(folder, "visible", title in shown)
        own = {a.name: a for a in system_actions(eng.scenario)}
        for name, h in self.action_widgets.items():
            a = own.get(name)
            shown = a is not None and a.shown(eng.scenario)
            set_if_changed(h, "visible", shown)
            if shown and a.kind == "item":
                options = (ALL, *a.options_of(eng.scenario))
                set_if_changed(h, "options", options)
                set_if_changed(h, "value", ALL if eng.item is None else options[eng.item + 1])
            elif shown and a.kind == "view":  # each scene's own value (the action's initial)
                set_if_changed(h, "value", float(min(max(getattr(eng, a.key), a.lo), a.hi)))
        set_if_changed(self.body_mesh, "value", eng.mesh.name if eng.mesh is not None and eng.mesh.name in asset_names()
             else INERTIA_SHAPE)
        for panel in self.panels.values():  # a new scene may have other sliders to sweep
            if hasattr(panel, "refresh"):
                panel.refresh()
        set_if_changed(self.warp, "value", float(np.log10(eng.warp)))
        self._sync_preset()
        set_if_changed(self.overlay, "value", eng.overlay_fidelity)
        set_if_changed(self.system, "value", _system_label(system))
        set_if_changed(self.fidelity, "value", eng.fidelity_choice)
        self._sync_choices()

    def _sync_choices(self) -> None:
        """auto's accuracy, shown while auto is the fidelity, and the systems' choice actions: the scene's.
        Each frame, on purpose: a value the engine refused (a raw client's) is set back on the page this way;
        ``set_if_changed`` sends only what differs."""
        eng = self.engine
        set_if_changed(self.accuracy, "options", tuple(controls.accuracy_options(eng.accuracy_choice)))
        set_if_changed(self.accuracy, "value", controls.accuracy_label(eng.accuracy_choice))
        set_if_changed(self.accuracy, "visible", eng.fidelity_choice == "auto")
        own = {a.name for a in system_actions(eng.scenario, "choice") if a.shown(eng.scenario)}
        for a in system_actions(None, "choice"):
            set_if_changed(self.action_widgets[a.name], "value", eng.choices.get(a.key, a.options[0]))
            set_if_changed(self.action_widgets[a.name], "visible", a.name in own)

    def _sync_preset(self) -> None:
        """The preset dropdown names the scene shown: its preset, "<preset> (edited)" once changed, or the
        scene's own name (an upload, a sweep point). Choosing a preset is then always a change of the
        dropdown's value, which reloads it, even the preset the scene came from."""
        eng = self.engine
        label = eng.preset + (EDITED if eng.edited else "")
        options = tuple(self.preset_names) if label in self.preset_names else (*self.preset_names, label)
        set_if_changed(self.preset, "options", options)
        set_if_changed(self.preset, "value", label)

    # ---- scene -----------------------------------------------------------------------------------

    def update(self, fr, plots_now: bool) -> None:
        """Show a frame's numbers (inside the session's ``client.atomic()``)."""
        eng = self.engine
        if eng.sliders_changed:
            eng.sliders_changed = False
            self.sync()
        if self.panels and eng.scenario is not self._panels_scene:  # any change of the scene, a slider's too
            self._panels_scene = eng.scenario
            for panel in self.panels.values():  # results of the earlier scene are marked stale
                if hasattr(panel, "scene_changed"):
                    panel.scene_changed()
        if plots_now:  # before the flag below is cleared: the sphere's chart reads it too
            self.energy.update(eng, changed=eng.plots_changed)
        if plots_now and eng.plots_changed:
            eng.plots_changed = False
            if not self.compare_plots.update(eng, self.plots):  # compare mode draws both runs instead
                plots.update_plots(self.plots, eng.plot_data(), eng.has_overlay, eng.overlay_title())
            self.readout_md.content = _readout_md(eng)
            set_if_changed(self.compare_md, "content", compare_readout_md(eng))
            set_if_changed(self.details_md, "content", _details_md(eng))
            set_if_changed(self.start_md, "content", eng.start_note())
        if plots_now:
            self._sync_preset()  # "(edited)" after a slider change, which does not resync the panel
            self.compare.sync()  # "off" when a new scene could not take the difference
            self.challenge.update()  # the race in words
        set_if_changed(self.badge_md, "content", eng.badge())  # cached: computed once per scenario, off this thread
        self._sync_choices()  # follow the dropdowns, an upload, an undo, a system change
        for key, value in eng.guard.take_revert().items():  # a rejected value's slider shows the last good one
            set_if_changed(self.sliders[key], "value", value)
        set_if_changed(self.upload_md, "content", _upload_md(eng.upload_note))
        note = edits.shown_note(eng.guard, fr.status, words.status_words(fr.message or ""))
        self.notes.show(note, can_undo=bool(eng.guard.undo))
        beside = note is not None and note.reason == eng.error  # shown under its slider: not again up here
        set_if_changed(self.error_md, "content", f"<span style='color:#c00'>**Rejected:** {plain(eng.error)}</span>"
             if eng.error and not beside else "")
        state = "playing" if eng.playing else "paused"
        if fr.status != "running":
            state = fr.status + (": " + words.status_words(fr.message) if fr.message else "")
        warp = f"warp {eng.warp:.3g}x"
        reached = eng.achieved_warp  # measured over the last second of playing (app.engine.clock)
        if eng.playing and fr.status == "running" and reached < 0.8 * eng.warp:
            warp += f" (reaching {reached:.3g}x: as fast as this machine integrates)"
        build = physics.kernel_status()
        prep = f" · preparing the fast integrator: {build.elapsed:.0f} s" if build.state == "pending" else ""
        self.share.tick()  # the browser keeps the last scene (throttled)
        set_if_changed(self.status_md, "content",
                       f"**Quasirigid explorer** · {state} · {warp}{prep}{self.motion.status()}"
                       f"{self.share.status()}")


def _build_sliders(gui, values: dict[str, float]) -> tuple[dict, dict]:
    """Folders of sliders; returns (key -> slider handle, folder title -> folder handle)."""
    sliders, folders = {}, {}
    reg = controls.registry()
    for title, keys in reg.folders:
        with gui.add_folder(title, expand_by_default=title == reg.folders[0][0]) as folder:
            folders[title] = folder
            for key in keys:
                p = reg.by_key[key]
                lo, hi = controls.slider_range(p, values[key])
                sliders[key] = gui.add_slider(p.text, min=lo, max=hi, step=p.step,
                                              initial_value=min(max(values[key], lo), hi), hint=p.hint)
    return sliders, folders


def _upload_md(note: tuple[str, str] | None) -> str:
    """The upload's outcome, under the Load button: red for a refusal. It stands in for viser's own "File uploaded
    successfully", which the page's script rewords (app.panel.typed_numbers), since a file received may be refused."""
    if note is None:
        return ""
    kind, text = note  # a refusal echoes the file's keys and values: shown as text, never as markup
    return f"<span style='color:{'#c00' if kind == 'refused' else '#555'}'>{plain(text)}</span>"


def _digits(*values: float, most: int = 7) -> int:
    """Decimals the slider's box shows: enough for each of ``values`` (0.001 needs 3), at most ``most``."""
    digits = 0
    for x in values:
        while digits < most and np.isfinite(x) and round(x, digits) != x:
            digits += 1
    return digits


def _system_label(system: str) -> str:
    return next(label for label, name in controls.SYSTEM_LABELS.items() if name == system)


def _readout_md(eng: Engine) -> str:
    """One ``name = value`` line per readout (the browser test reads them back)."""
    d = eng.readouts()
    return "  \n".join(f"{k} = {v}" for k, v in d.items()) + f"  \npreset: {eng.preset}"


def _details_md(eng: Engine) -> str:
    """The Details folder: model, method and the raw attitude; the averaged model's conditions as formulas."""
    d = eng.details()
    lines = "  \n".join(f"{k} = {v}" for k, v in d.items())
    conds = eng.badge_details()
    return lines + ("  \n" + conds if conds else "")


