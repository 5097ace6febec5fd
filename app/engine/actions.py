"""What a tab's GUI actions do (play, step, reset, preset, system, fidelity, undo...): one method each, looked
up in ``ACTIONS`` by the name ``Engine.request`` queued. They run on the session's loop thread, in ``tick``.
Mixed into ``app.engine.engine.Engine``: they read and set its run, scenario, values, buffers and clock."""

from __future__ import annotations

import dataclasses
import math

import physics

from . import controls, edits, parts, presets
from .buffers import RECENT, VIEWS, WHOLE_RUN
from .clock import FRAME_HZ
from .compare import set_compare, undo_compare
from .workers import OVERLAYS


class ActionsMixin:
    # ---- actions (loop thread): one handler each, looked up in ACTIONS ----------------------------
    def _act(self, action: str, value) -> None:
        handler = ACTIONS.get(action)
        if handler is None:
            raise ValueError(f"unknown action {action!r}")
        handler(self, value)

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
        self.sliders_changed = self.plots_changed = self.overlay_dirty = True

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
        self._run_choice(value, self.accuracy_choice, self.pivot_choice)

    def _accuracy(self, value) -> None:
        """Another accuracy for auto (rad; None: physics.DEFAULT_ACCURACY): auto may then pick another model,
        which goes on from the state carried as a fidelity chosen by hand does."""
        if value is not None and not (isinstance(value, float) and 0.0 < value < math.inf):
            raise ValueError(f"auto's accuracy {value!r}: expected a positive number of rad or the default")
        self._run_choice(self.fidelity_choice, value, self.pivot_choice)

    def _pivot(self, value) -> None:
        """What a spherical pendulum's spring and damper act on (physics.PIVOTS: the Cardan angles, or the arm's
        direction, which goes on through the gimbal pole); the swing goes on from the state carried."""
        if value not in physics.PIVOTS:
            raise ValueError(f"pivot {value!r}: expected one of {', '.join(physics.PIVOTS)}")
        self._run_choice(self.fidelity_choice, self.accuracy_choice, value)

    def _run_choice(self, fidelity: str, accuracy: float | None, pivot: str) -> None:
        sc = with_choices(self.scenario, fidelity, accuracy, pivot)
        kept = self.run.retune(sc, keep_state=not self.restart_on_change)
        self.fidelity_choice, self.accuracy_choice, self.pivot_choice = fidelity, accuracy, pivot
        self.error = ""
        if kept:
            self.log_retune(sc)
            self.overlay_dirty = True
            self.scene_changed = True  # the full model draws the moving mass; the averaged one has none
        else:
            self._restarted()
        self._note_edit(kept)

    def _restart_on_change(self, value) -> None:
        self.restart_on_change = bool(value)

    def _view(self, value) -> None:
        self.view = value if value in VIEWS else "inertial"
        self.trail.clear()  # the trail means something else in the other frame
        self.scene_changed = True

    def _exaggeration(self, value) -> None:
        self.exaggeration = float(value)

    def _plots(self, value) -> None:
        if value not in (WHOLE_RUN, RECENT):
            raise ValueError(f"plots show {value!r}: expected {WHOLE_RUN!r} or {RECENT!r}")
        self.plot_span = value
        self.plots_changed = True

    def _overlay(self, value) -> None:
        if not isinstance(value, str) or value not in OVERLAYS:
            raise ValueError(f"overlay {str(value)[:40]!r}: expected one of {', '.join(OVERLAYS)}")
        self.overlay_fidelity = value
        self.overlay_dirty = True
        self.plots_changed = True

    def _tune(self, _value) -> None:
        self._apply_values({controls.TUNE_KEY: "resonant"})

    def _bob(self, value) -> None:
        n = len(parts.array_items(self.scenario))
        self.bob = None if value in (None, "all") or n == 0 else min(max(int(value), 0), n - 1)
        self.values.update({k: v for k, v in controls.values_of(self.scenario, self.bob).items()
                            if k.startswith("pendulum.")})
        self.sliders_changed = True

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
    "accuracy": ActionsMixin._accuracy, "pivot": ActionsMixin._pivot,
    "restart_on_change": ActionsMixin._restart_on_change, "view": ActionsMixin._view,
    "exaggeration": ActionsMixin._exaggeration, "overlay": ActionsMixin._overlay, "plots": ActionsMixin._plots,
    "tune": ActionsMixin._tune, "bob": ActionsMixin._bob, "polhode": ActionsMixin._polhode,
    "sphere": ActionsMixin._sphere,
    "mesh": ActionsMixin._mesh, "upload": ActionsMixin._upload, "scenario": ActionsMixin._scenario,
    "undo": ActionsMixin._undo, "reload": ActionsMixin._reload,
    "compare": set_compare,  # app.engine.compare: a second run with one difference, or off
}



def with_choices(sc: physics.Scenario, fidelity: str, accuracy: float | None, pivot: str) -> physics.Scenario:
    """``sc`` with the panel's choices, kept across slider edits: the fidelity, auto's accuracy and a spherical
    pendulum's pivot (a scene without one keeps the choice for a later one). ``sc`` itself when it has them."""
    if (sc.run.fidelity, sc.run.accuracy) != (fidelity, accuracy):
        sc = sc.replace(run=dataclasses.replace(sc.run, fidelity=fidelity, accuracy=accuracy))
    if sc.pendulum is not None and sc.pendulum.pivot != pivot:
        sc = sc.replace(pendulum=dataclasses.replace(sc.pendulum, pivot=pivot))
    return sc


def pivot_of(sc: physics.Scenario) -> str:
    return sc.pendulum.pivot if sc.pendulum is not None else physics.PIVOTS[0]
