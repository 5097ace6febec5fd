"""One tab's control panel: the status line, readouts, plots, playback, model, sliders, view, file and
the lazily built study panels. Callbacks only record requests on the engine; ``update`` shows a frame's
numbers and ``sync`` pushes slider values and ranges after a scene change.
"""

from __future__ import annotations

import numpy as np
import viser

import physics

from ..engine import controls, edits, parts, presets, words
from ..engine.compare import readout_md as compare_readout_md
from ..engine.engine import Engine
from ..engine.mesh import INERTIA_SHAPE, asset_names
from ..engine.workers import OVERLAYS
from ..handles import set_if_changed
from ..replay.export import ReplayButton
from ..share.panel import SharePanel
from . import plots
from .compare_panel import ComparePanel
from .compare_plots import ComparePlots
from .control_notes import NotePlace
from .energy_plot import EnergyChart
from .playbar import Playbar

EDITED = " (edited)"  # the preset dropdown's name for a preset changed since it was loaded


class Panel:
    """The GUI of one browser tab."""

    def __init__(self, client: viser.ClientHandle, engine: Engine, restore: bool = True):
        self.client = client
        self.engine = engine
        self.restore = restore  # whether the browser's last scene may replace the one the tab starts with
        self._build_gui()

    def _build_gui(self) -> None:
        gui, eng = self.client.gui, self.engine
        gui.configure_theme(control_width="large")
        self.status_md = gui.add_markdown("**Quasirigid explorer**")
        self.playbar = Playbar(gui, eng)  # right under the status line: reached without scrolling
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
            self.tune_btn = gui.add_button("Tune to resonance", hint="spherical pendulum: k = resonant (MODELS B.5)")
        self.panels: dict = {}
        self._panels_scene = None  # the scenario the study panels last judged their results against
        self.sliders, self.folders = _build_sliders(gui, eng.values)
        folder_of = {key: self.folders[title] for title, keys in controls.FOLDERS for key in keys}
        self.notes = NotePlace(gui, self.sliders, folder_of, self.error_md.order,
                               undo=lambda: eng.request("undo"), reset=lambda: eng.request("reload"))
        with self.folders["Pendulum damper"]:
            self.bob = gui.add_dropdown("bob", ["all", "1", "2", "3"], initial_value="all",
                                        hint="plane pendulums: which bob the sliders above edit")
            self.pivot = gui.add_dropdown("pivot", list(physics.PIVOTS), initial_value=eng.pivot_choice,
                                          visible=eng.scenario.pendulum is not None,
                                          hint="what the spring and damper act on: cardan, the two gimbal angles "
                                          "(the paper's model; a swing through the gimbal pole stops with a spring); "
                                          "isotropic, the arm's direction (the same for small swings, and it goes on "
                                          "through the pole)")
        with gui.add_folder("View"):
            self.view = gui.add_dropdown("Frame", ["inertial", "body"], initial_value="inertial",
                                         hint="inertial: K fixed and pointing up; body: the body stays still")
            self.exag = gui.add_slider("exaggerate u (x)", min=1.0, max=1000.0, step=1.0,
                                       initial_value=float(eng.exaggeration),
                                       hint="the mass's displacement is drawn this many times larger (each scene "
                                       "starts with a factor that keeps it within the body; shown beside the mass)")
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
        self.compare = ComparePanel(gui, eng)  # the Compare folder: a second run with one difference
        with gui.add_folder("File", expand_by_default=False):
            self.toml_btn = gui.add_button("Download scenario (TOML)")
            self.csv_btn = gui.add_button("Download trajectory (CSV)")
            self.upload = gui.add_upload_button("Load scenario (TOML)", mime_type=".toml",
                                                hint="a scenario file, as `python -m physics` reads (64 kB at most)")
            self.replay = ReplayButton(gui, eng, self.client)  # the scene as an offline HTML replay (app.replay.export)
        self.share = SharePanel(gui, eng, self.client, restore=self.restore)  # code, link, last scene (share_panel)
        self._lazy_panel("Speed vs accuracy", "speed_panel", "SpeedPanel",
                         lambda sc: eng.request("scenario", (sc, f"{eng.preset} (recommended method)")))
        self._lazy_panel("Sweep", "sweep_panel", "SweepPanel",
                         lambda sc: eng.request("scenario", (sc, "sweep point")), scene=self.client.scene)

        def on(handle, action, convert=lambda v: v):
            @handle.on_update
            def _(event):
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

        click(self.tune_btn, "tune")
        on(self.warp, "warp", lambda v: 10.0 ** float(v))
        on(self.restart, "restart_on_change")

        @self.preset.on_update
        def _(event):
            # the scene's own name ("... (edited)", an upload) is not a preset to load
            if event.client is not None and self.preset.value in self.preset_names:
                eng.request("preset", self.preset.value)

        on(self.system, "system", lambda v: controls.SYSTEM_LABELS[v])
        on(self.fidelity, "fidelity")
        on(self.accuracy, "accuracy", lambda v: controls.accuracy_options(eng.accuracy_choice)[v])
        on(self.overlay, "overlay")
        on(self.plots.span, "plots", lambda v: plots.SPANS[v])
        on(self.view, "view")
        on(self.exag, "exaggeration")
        on(self.polhode, "polhode")
        on(self.sphere, "sphere")
        on(self.body_mesh, "mesh")
        on(self.bob, "bob", lambda v: None if v == "all" else int(v) - 1)
        on(self.pivot, "pivot")
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
        def _(event):
            if event.client is None:
                return
            self.engine.request_value(key, float(slider.value), limits=(slider.min, slider.max))

    def sync(self) -> None:
        """After a preset or system change: slider values, ranges and which folders apply."""
        eng = self.engine
        system = eng.scenario.system
        for key, slider in self.sliders.items():  # assign only what differs: each assignment is a message
            p = controls.BY_KEY[key]
            lo, hi = controls.slider_range(p, eng.values[key])
            set_if_changed(slider, "min", lo)
            set_if_changed(slider, "max", hi)
            set_if_changed(slider, "value", min(max(eng.values[key], lo), hi))
            set_if_changed(slider, "disabled", system not in p.systems)
        shown = controls.folders_of(system)  # the body's, the start's and the system's own
        for title, folder in self.folders.items():
            set_if_changed(folder, "visible", title in shown)
        set_if_changed(self.tune_btn, "visible", controls.owns_table(system, controls.TUNE_KEY))
        n = len(parts.array_items(eng.scenario))
        set_if_changed(self.bob, "visible", n > 0)
        if n > 0:
            set_if_changed(self.bob, "options", ("all", *(str(i + 1) for i in range(n))))
            set_if_changed(self.bob, "value", "all" if eng.bob is None else str(eng.bob + 1))
        set_if_changed(self.body_mesh, "value", eng.mesh.name if eng.mesh is not None and eng.mesh.name in asset_names()
             else INERTIA_SHAPE)
        set_if_changed(self.exag, "value", float(eng.exaggeration))  # each scene's own factor (app.engine.mass_view)
        set_if_changed(self.exag, "visible", eng.scenario.mass is not None)
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
        """auto's accuracy, shown while auto is the fidelity, and the spherical pendulum's pivot: the scene's.
        Each frame, on purpose: a value the engine refused (a raw client's) is set back on the page this way;
        ``set_if_changed`` sends only what differs."""
        eng = self.engine
        set_if_changed(self.accuracy, "options", tuple(controls.accuracy_options(eng.accuracy_choice)))
        set_if_changed(self.accuracy, "value", controls.accuracy_label(eng.accuracy_choice))
        set_if_changed(self.accuracy, "visible", eng.fidelity_choice == "auto")
        set_if_changed(self.pivot, "value", eng.pivot_choice)
        set_if_changed(self.pivot, "visible", eng.scenario.pendulum is not None)

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
        if plots_now:
            self._sync_preset()  # "(edited)" after a slider change, which does not resync the panel
            self.compare.sync()  # "off" when a new scene could not take the difference
        set_if_changed(self.badge_md, "content", eng.badge())  # cached: computed once per scenario, off this thread
        self._sync_choices()  # follow the dropdowns, an upload, an undo, a system change
        for key, value in eng.guard.take_revert().items():  # a rejected value's slider shows the last good one
            set_if_changed(self.sliders[key], "value", value)
        note = edits.shown_note(eng.guard, fr.status, words.status_words(fr.message or ""))
        self.notes.show(note, can_undo=bool(eng.guard.undo))
        beside = note is not None and note.reason == eng.error  # shown under its slider: not again up here
        set_if_changed(self.error_md, "content", f"<span style='color:#c00'>**Rejected:** {eng.error}</span>"
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
                       f"**Quasirigid explorer** · {state} · {warp}{prep}{self.share.status()}")


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


