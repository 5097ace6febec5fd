"""What a tab's GUI actions do (play, step, reset, preset, system, fidelity, undo...): one method each, looked
up in ``ACTIONS`` by the name ``Engine.request`` queued. They run on the session's loop thread, in ``tick``.
Mixed into ``app.engine.engine.Engine``: they read and set its run, scenario, values, buffers and clock."""

from __future__ import annotations

import dataclasses
import math

import physics

from . import controls, edits, presets
from .buffers import RECENT, VIEWS, WHOLE_RUN
from .clock import FRAME_HZ
from .compare import set_compare, undo_compare
from .workers import OVERLAYS


class ActionsMixin:
    # ---- actions (loop thread): one handler each, looked up in ACTIONS ----------------------------
    def _act(self, action: str, value) -> None:
        handler = ACTIONS.get(action)
        if handler is not None:
            handler(self, value)
            return
        own = [a for a in system_actions(self.scenario) if a.name == action]
        known = own or [a for a in system_actions(None) if a.name == action]
        if not known:
            raise ValueError(f"unknown action {action!r}")
        getattr(self, f"_{known[0].kind}_action")(known[0], value, bool(own))

    # ---- a system's own actions (physics.figure.Action), by kind -----------------------------------
    def _button_action(self, a, _value, own: bool) -> None:
        """Its edits, applied as slider values are (another system's are kept for later, as a slider's)."""
        self._apply_values(a.apply(self.scenario))

    def _choice_action(self, a, value, own: bool) -> None:
        """The option for the scenario key ``a.key``, kept across edits and scenes; the run goes on from its
        state (a spherical pendulum's pivot: the swing goes on)."""
        if not isinstance(value, str) or value not in a.options:
            raise ValueError(f"{a.label} {value!r}: expected one of {', '.join(a.options)}")
        self._run_choice(self.fidelity_choice, self.accuracy_choice, {**self.choices, a.key: value})

    def _item_action(self, a, value, own: bool) -> None:
        """Which item of the scene's array table the sliders edit (0-based; None or "all": every item); the
        sliders show its values."""
        n = len(a.options_of(self.scenario)) if own else 0
        self.item = None if value in (None, "all") or n == 0 else min(max(int(value), 0), n - 1)
        system = self.scenario.system
        own_keys = {p.key for p in controls.registry().params if system in p.systems and not p.base}
        self.values.update({k: v for k, v in controls.values_of(self.scenario, self.item).items() if k in own_keys})
        self.sliders_changed = True

    def _view_action(self, a, value, own: bool) -> None:
        """A value the figure is drawn with (physics.figure.View's field ``a.key``), within [lo, hi]."""
        v = float(value)
        if not math.isfinite(v):
            raise ValueError(f"{a.label} {value!r}: expected a number in [{a.lo:g}, {a.hi:g}]")
        self.view_values[a.key] = min(max(v, a.lo), a.hi)

    def _undo(self, _value) -> None:
        """Back to just before the last change: its parameters and the run's state then (the clock too)."""
        snap = self.guard.take_undo()
        if snap is None:
            return
        t = snap.restore(self)
        if snap.epoch != self.guard.epoch:
            self._restarted()  # the change (or a reset since) restarted the buffers: they start again from t
        else:
            for buffer in (self.plot, getattr(self, "plot_all", None), self.history):
                if buffer is not None:
                    edits.rewind(buffer, t)
            self.trail.clear()
            self.polhode.clear()
            self._record(self.run.last)  # the state restored, at t
        undo_compare(self, snap)  # the second run (compare mode) goes back to the same change
        self.edit_dE, self.edit_note = None, ""
        self.error = ""
        self.shape = self._shape(self.scenario)
        if self.static_signature() != self._drawn:
            self.scene_changed = True
        self.sliders_changed = self.plots_changed = self.prediction.dirty = True

    def _reload(self, _value) -> None:
        """The scene as it was loaded, from t = 0: a fault's other way out."""
        self._load(*self.guard.loaded)
        self.error = ""

    def _play(self, _value) -> None:
        self.playing = True

    def _pause(self, _value) -> None:
        self.playing = False

    def _toggle(self, _value) -> None:
        self.playing = not self.playing

    def _step(self, _value) -> None:
        self.playing = False
        self._advance(self.warp / FRAME_HZ)

    def _reset(self, _value) -> None:
        self.run.reset()
        self.error = ""
        self._restarted()

    def _set_warp(self, value) -> None:
        self.clock.set_warp(float(value))

    def _preset(self, value) -> None:
        from .mesh import asset_names

        kept = self.mesh.name if self.mesh is not None and self.mesh.name in asset_names() else None
        sc = presets.load_preset(value)
        self.mesh = None  # a preset brings its own body...
        self._load(sc, value)
        self.error = ""
        if kept is not None:  # ...but "body drawn as" is the user's choice: it stays where the preset's parts fit
            try:
                self._use_mesh(kept, label=f"{value} (body: {kept})")
            except physics.ScenarioError as exc:
                self.mesh = None
                self._load(sc, value)
                self.error = f"body drawn as {kept}: does not fit this preset ({exc}); its own body is drawn"
        overlay = presets.overlay_of(value)
        if overlay is not None:  # a figure's preset shows the cheaper model its figure compares with
            self._overlay(overlay)
            self.sliders_changed = True  # the panel shows the overlay chosen

    def _system(self, value) -> None:
        if value != self.scenario.system:
            *tries, last = presets.system_scenes(self.scenario, value)  # the current body where it fits
            for sc, name in tries:
                try:
                    self._load(sc, name)
                    break
                except physics.ScenarioError:
                    continue
            else:
                self.mesh = None  # the template's own body: a mesh no longer describes it
                self._load(*last)
            self.error = ""

    def _fidelity(self, value) -> None:
        """Another fidelity from now on, with the state carried (K and the attitude kept) unless "restart on
        change" is set or the new model is a closed form, which has no state and starts at t = 0."""
        self._run_choice(value, self.accuracy_choice, self.choices)

    def _accuracy(self, value) -> None:
        """Another accuracy for auto (rad; None: physics.DEFAULT_ACCURACY): auto may then pick another model,
        which goes on from the state carried as a fidelity chosen by hand does."""
        if value is not None and not (isinstance(value, float) and 0.0 < value < math.inf):
            raise ValueError(f"auto's accuracy {value!r}: expected a positive number of rad or the default")
        self._run_choice(self.fidelity_choice, value, self.choices)

    def _run_choice(self, fidelity: str, accuracy: float | None, choices: dict) -> None:
        sc = with_choices(self.scenario, fidelity, accuracy, choices)
        kept = self.run.retune(sc, keep_state=not self.restart_on_change)
        self.fidelity_choice, self.accuracy_choice, self.choices = fidelity, accuracy, dict(choices)
        self.error = ""
        if kept:
            self.log_retune(sc)
            self.prediction.dirty = True
            self.scene_changed = True  # another model may draw other parts (the averaged one has no displacement)
        else:
            self._restarted()
        self._note_edit(kept)

    def _restart_on_change(self, value) -> None:
        self.restart_on_change = bool(value)

    def _view(self, value) -> None:
        self.view = value if value in VIEWS else "inertial"
        self.trail.clear()  # the trail means something else in the other frame
        self.scene_changed = True

    def _plots(self, value) -> None:
        if value not in (WHOLE_RUN, RECENT):
            raise ValueError(f"plots show {value!r}: expected {WHOLE_RUN!r} or {RECENT!r}")
        self.plot_span = value
        self.plots_changed = True

    def _overlay(self, value) -> None:
        if not isinstance(value, str) or value not in OVERLAYS:
            raise ValueError(f"overlay {str(value)[:40]!r}: expected one of {', '.join(OVERLAYS)}")
        self.prediction.fidelity = value
        self.prediction.dirty = True
        self.plots_changed = True

    def _polhode(self, value) -> None:
        self.show_polhode = bool(value)
        self.polhode.clear()

    def _sphere(self, value) -> None:
        self.show_sphere = bool(value)  # K's path is kept while hidden: shown again, it has the whole run

    def _mesh(self, value) -> None:
        self._use_mesh(value)

    def _upload(self, value) -> None:
        """(file name, bytes) from the browser: through the parser, size-capped."""
        from .upload import display_name, parse_upload

        name, content = value
        sc = parse_upload(name, content)
        self.mesh = None
        self._load(sc, f"upload {display_name(name)}")
        self.error = ""

    def _scenario(self, value) -> None:
        """(Scenario, label) from a panel: a sweep's point, a recommended method."""
        sc, label = value
        self.mesh = None
        self._load(sc, label)
        self.error = ""

    def _use_mesh(self, name: str, label: str | None = None) -> None:
        """Draw the body as a mesh from assets/meshes, or as the uniform shape of its inertia again
        ("inertia shape"). The mesh, a uniform solid of mass M scaled to keep A + B + C, gives A, B, C.
        ``label``: the scene's name (default "mesh NAME")."""
        from . import mesh as meshes

        if name in (None, "", meshes.INERTIA_SHAPE):
            self.mesh = None
            self.shape = self._shape(self.scenario)
            self.scene_changed = True
            return
        path = meshes.asset_path(name)  # only names the assets folder holds: no path comes from a browser
        body = meshes.scaled_to(meshes.load_mesh(path, self.scenario.body.M), self.scenario.body)
        sc = meshes.with_mesh(self.scenario, body)
        previous, self.mesh = self.mesh, body
        try:
            self._load(sc, label or f"mesh {name}")
        except physics.ScenarioError:
            self.mesh = previous  # the scene stays as it was, drawn as before
            raise




# action name -> handler; ``ActionsMixin.request(name, value)`` queues one, ``tick`` applies it
ACTIONS = {
    "play": ActionsMixin._play, "pause": ActionsMixin._pause, "toggle": ActionsMixin._toggle,
    "step": ActionsMixin._step, "reset": ActionsMixin._reset, "warp": ActionsMixin._set_warp,
    "preset": ActionsMixin._preset, "system": ActionsMixin._system, "fidelity": ActionsMixin._fidelity,
    "accuracy": ActionsMixin._accuracy,
    "restart_on_change": ActionsMixin._restart_on_change, "view": ActionsMixin._view,
    "overlay": ActionsMixin._overlay, "plots": ActionsMixin._plots, "polhode": ActionsMixin._polhode,
    "sphere": ActionsMixin._sphere,
    "mesh": ActionsMixin._mesh, "upload": ActionsMixin._upload, "scenario": ActionsMixin._scenario,
    "undo": ActionsMixin._undo, "reload": ActionsMixin._reload,
    "compare": set_compare,  # app.engine.compare: a second run with one difference, or off
}



def system_actions(sc: physics.Scenario | None, kind: str | None = None) -> tuple:
    """The actions (physics.figure.Action) of ``sc``'s system, or of every registered system (None), of
    ``kind`` if given; one per name, the first system's."""
    systems = [physics.get_system(sc.system)] if sc is not None else list(physics.SYSTEMS.values())
    out: dict = {}
    for s in systems:
        for a in s.actions:
            if kind in (None, a.kind):
                out.setdefault(a.name, a)
    return tuple(out.values())


def choices_of(sc: physics.Scenario, kept: dict | None = None) -> dict[str, str]:
    """Every choice action's option as ``sc`` has it; a choice the scene has nothing for keeps its value in
    ``kept`` (a later scene that has it gets it), else its first option."""
    kept = kept or {}
    own = {a.key for a in system_actions(sc, "choice") if a.shown(sc)}
    return {a.key: a.value_of(sc) if a.key in own else kept.get(a.key, a.options[0])
            for a in system_actions(None, "choice")}


def with_choices(sc: physics.Scenario, fidelity: str, accuracy: float | None, choices: dict) -> physics.Scenario:
    """``sc`` with the panel's choices, kept across slider edits: the fidelity, auto's accuracy and the system's
    choice actions' options (a scene without what one sets keeps the choice for a later one). ``sc`` itself when
    it has them all, so that a slider change builds and validates its scenario once."""
    if (sc.run.fidelity, sc.run.accuracy) != (fidelity, accuracy):
        sc = sc.replace(run=dataclasses.replace(sc.run, fidelity=fidelity, accuracy=accuracy))
    system = physics.get_system(sc.system)
    edits = {a.key: choices[a.key] for a in system_actions(sc, "choice")
             if a.key in choices and a.shown(sc) and a.value_of(sc) != choices[a.key]}
    if not edits:
        return sc
    data = sc.to_dict()
    for key, value in edits.items():
        if system.edit is not None:
            system.edit(data, key, value)
        else:
            physics.edit_dict(data, key, value, sc)
    return physics.Scenario.from_dict(data)
