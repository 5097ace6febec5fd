"""What a tab's GUI actions do (play, step, reset, preset, system, fidelity, undo...): one function each, looked
up in ``ACTIONS`` (by ``act``) by the name ``Engine.request`` queued. They run on the session's loop thread, in
``tick``. Each is a function of the engine (``eng``) and the action's value: they read and set its run, scenario,
values, buffers and clock, through its attributes and its loading and recording methods."""

from __future__ import annotations

import dataclasses
import math

import physics

from . import challenge, controls, edits, presets
from . import mesh as meshes
from .buffers import RECENT, VIEWS, WHOLE_RUN
from .clock import FRAME_HZ
from .compare import set_compare, undo_compare
from .upload import display_name, parse_upload
from .workers import OVERLAYS


# ---- actions (loop thread): one handler each, looked up in ACTIONS ----------------------------
def act(eng, action: str, value) -> None:
    """Apply the action ``action`` (a name ``Engine.request`` queued) with ``value`` to the engine ``eng``."""
    handler = ACTIONS.get(action)
    if handler is not None:
        handler(eng, value)
        return
    own = [a for a in system_actions(eng.scenario) if a.name == action]
    known = own or [a for a in system_actions(None) if a.name == action]
    if not known:
        raise ValueError(f"unknown action {action!r}")
    BY_KIND[known[0].kind](eng, known[0], value, bool(own))


# ---- a system's own actions (physics.figure.Action), by kind -----------------------------------
def _button_action(eng, a, _value, own: bool) -> None:
    """Its edits, applied as slider values are (another system's are kept for later, as a slider's)."""
    eng._apply_values(a.apply(eng.scenario))


def _choice_action(eng, a, value, own: bool) -> None:
    """The option for the scenario key ``a.key``, kept across edits and scenes; the run goes on from its
    state (a spherical pendulum's pivot: the swing goes on)."""
    if not isinstance(value, str) or value not in a.options:
        raise ValueError(f"{a.label} {value!r}: expected one of {', '.join(a.options)}")
    _run_choice(eng, eng.fidelity_choice, eng.accuracy_choice, {**eng.choices, a.key: value})


def _item_action(eng, a, value, own: bool) -> None:
    """Which item of the scene's array table the sliders edit (0-based; None or "all": every item); the
    sliders show its values."""
    n = len(a.options_of(eng.scenario)) if own else 0
    if value in (None, "all") or n == 0:
        eng.item = None
    else:
        number = _number_sent(value)
        if number is None or number != int(number):
            raise ValueError(f"{a.label} {value!r}: expected a whole number from 0 to {n - 1} or 'all'")
        eng.item = min(max(int(number), 0), n - 1)
    system = eng.scenario.system
    own_keys = {p.key for p in controls.registry().params if system in p.systems and not p.base}
    eng.values.update({k: v for k, v in controls.values_of(eng.scenario, eng.item).items() if k in own_keys})
    eng.sliders_changed = True


def _view_action(eng, a, value, own: bool) -> None:
    """A value the figure is drawn with (physics.figure.View's field ``a.key``), within [lo, hi]."""
    v = _number_sent(value)
    if v is None:
        raise ValueError(f"{a.label} {value!r}: expected a number in [{a.lo:g}, {a.hi:g}]")
    eng.view_values[a.key] = min(max(v, a.lo), a.hi)


def _undo(eng, _value) -> None:
    """Back to just before the last change: its parameters and the run's state then (the clock too)."""
    snap = eng.guard.take_undo()
    if snap is None:
        return
    t = snap.restore(eng)
    if snap.epoch != eng.guard.epoch:
        eng._restarted()  # the change (or a reset since) restarted the buffers: they start again from t
    else:
        for buffer in (eng.plot, getattr(eng, "plot_all", None), eng.history):
            if buffer is not None:
                edits.rewind(buffer, t)
        eng.trail.clear()
        eng.polhode.clear()
        eng._record(eng.run.last)  # the state restored, at t
    undo_compare(eng, snap)  # the second run (compare mode) goes back to the same change
    eng.edit_dE, eng.edit_note = None, ""
    eng.error = ""
    eng.shape = eng._shape(eng.scenario)
    if eng.static_signature() != eng._drawn:
        eng.scene_changed = True
    eng.sliders_changed = eng.plots_changed = eng.prediction.dirty = True


def _reload(eng, _value) -> None:
    """The scene as it was loaded, from t = 0: a fault's other way out."""
    eng._load(*eng.guard.loaded)
    eng.error = ""


def _play(eng, _value) -> None:
    eng.playing = True


def _pause(eng, _value) -> None:
    eng.playing = False


def _toggle(eng, _value) -> None:
    eng.playing = not eng.playing


def _step(eng, _value) -> None:
    eng.playing = False
    eng._advance(eng.warp / FRAME_HZ)


def _reset(eng, _value) -> None:
    if eng.challenge is not None:  # the same attempt again, from its start
        challenge.start(eng, (eng.challenge.level, eng.challenge.seed))
        return
    eng.run.reset()
    eng.error = ""
    eng._restarted()


def _set_warp(eng, value) -> None:
    warp = _number_sent(value)
    if warp is None:  # float() would pass "inf" on as a number, and say "could not convert string" of the rest
        raise ValueError(f"time warp {value!r}: expected a number of times real time "
                         f"({presets.WARP_MIN:g}x to {presets.WARP_MAX:g}x)")
    eng.clock.set_warp(warp)


def _number_sent(value) -> float | None:
    """A finite number a client sent as a number or as text ("2.5"), else None (a word, a table, NaN, inf)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        return None
    try:
        v = float(value)
    except (ValueError, OverflowError):  # "abc"; an int of a thousand digits
        return None
    return v if math.isfinite(v) else None


def _preset(eng, value) -> None:
    kept = eng.mesh.name if eng.mesh is not None and eng.mesh.name in meshes.asset_names() else None
    try:
        sc = presets.load_preset(value)
    except (KeyError, TypeError):  # not a preset's name (TypeError: a list from a raw client is unhashable)
        raise ValueError(f"preset {str(value)[:40]!r}: expected one of the presets ({len(presets.preset_names())}, "
                         "as the Scene menu lists them)") from None
    eng.mesh = None  # a preset brings its own body...
    eng._load(sc, value)
    eng.error = ""
    if kept is not None:  # ...but "body drawn as" is the user's choice: it stays where the preset's parts fit
        try:
            _use_mesh(eng, kept, label=f"{value} (body: {kept})")
        except physics.ScenarioError as exc:
            eng.mesh = None
            eng._load(sc, value)
            eng.error = f"body drawn as {kept}: does not fit this preset ({exc}); its own body is drawn"
    overlay = presets.overlay_of(value)
    if overlay is not None:  # a figure's preset shows the cheaper model its figure compares with
        _overlay(eng, overlay)
        eng.sliders_changed = True  # the panel shows the overlay chosen


def _system(eng, value) -> None:
    if value != eng.scenario.system:
        *tries, last = presets.system_scenes(eng.scenario, value)  # the current body where it fits
        for sc, name in tries:
            try:
                eng._load(sc, name)
                break
            except physics.ScenarioError:
                continue
        else:
            eng.mesh = None  # the template's own body: a mesh no longer describes it
            eng._load(*last)
        eng.error = ""


def _fidelity(eng, value) -> None:
    """Another fidelity from now on, with the state carried (K and the attitude kept) unless "restart on
    change" is set or the new model is a closed form, which has no state and starts at t = 0."""
    _run_choice(eng, value, eng.accuracy_choice, eng.choices)


def _accuracy(eng, value) -> None:
    """Another accuracy for auto (rad; None: physics.DEFAULT_ACCURACY): auto may then pick another model,
    which goes on from the state carried as a fidelity chosen by hand does."""
    if value is not None and not (isinstance(value, float) and 0.0 < value < math.inf):
        raise ValueError(f"auto's accuracy {value!r}: expected a positive number of rad or the default")
    _run_choice(eng, eng.fidelity_choice, value, eng.choices)


def _run_choice(eng, fidelity: str, accuracy: float | None, choices: dict) -> None:
    challenge.stop(eng)  # another model: the race is no longer the level's
    sc = with_choices(eng.scenario, fidelity, accuracy, choices)
    kept = eng.run.retune(sc, keep_state=not eng.restart_on_change)
    eng.fidelity_choice, eng.accuracy_choice, eng.choices = fidelity, accuracy, dict(choices)
    eng.error = ""
    if kept:
        eng.log_retune(sc)
        eng.prediction.dirty = True
        eng.scene_changed = True  # another model may draw other parts (the averaged one has no displacement)
    else:
        eng._restarted()
    eng._note_edit(kept)


def _restart_on_change(eng, value) -> None:
    eng.restart_on_change = bool(value)


def _view(eng, value) -> None:
    eng.view = value if value in VIEWS else "inertial"
    eng.trail.clear()  # the trail means something else in the other frame
    eng.scene_changed = True


def _plots(eng, value) -> None:
    if value not in (WHOLE_RUN, RECENT):
        raise ValueError(f"plots show {value!r}: expected {WHOLE_RUN!r} or {RECENT!r}")
    eng.plot_span = value
    eng.plots_changed = True


def _overlay(eng, value) -> None:
    if not isinstance(value, str) or value not in OVERLAYS:
        raise ValueError(f"overlay {str(value)[:40]!r}: expected one of {', '.join(OVERLAYS)}")
    eng.prediction.fidelity = value
    eng.prediction.dirty = True
    eng.plots_changed = True


def _polhode(eng, value) -> None:
    eng.show_polhode = bool(value)
    eng.polhode.clear()


def _sphere(eng, value) -> None:
    eng.show_sphere = bool(value)  # K's path is kept while hidden: shown again, it has the whole run


def _mesh(eng, value) -> None:
    _use_mesh(eng, value)


def _upload(eng, value) -> None:
    """(file name, bytes) from the browser: through the parser, size-capped. What came of it is said beside the
    upload button (``eng.upload_note``), not at the top of the panel: loaded, or refused with physics's reason."""
    name, content = value
    mesh = eng.mesh
    try:
        sc = parse_upload(name, content)
        eng.mesh = None  # the file's body is drawn as its own inertia shape
        eng._load(sc, f"upload {display_name(name)}")  # a ScenarioError here too leaves the scene as it was
    except physics.ScenarioError as exc:
        eng.mesh = mesh
        eng.upload_note = ("refused", f"Not loaded: {exc}. The scene is unchanged.")
        return
    eng.error = ""
    eng.upload_note = ("loaded", f"Loaded {display_name(name)}; it starts at t = 0.")


def _scenario(eng, value) -> None:
    """(Scenario, label) from a panel: a sweep's point, a recommended method."""
    sc, label = value
    eng.mesh = None
    eng._load(sc, label)
    eng.error = ""


def _use_mesh(eng, name: str, label: str | None = None) -> None:
    """Draw the body as a mesh from assets/meshes, or as the uniform shape of its inertia again
    ("inertia shape"). The mesh, a uniform solid of mass M scaled to keep A + B + C, gives A, B, C.
    ``label``: the scene's name (default "mesh NAME")."""
    if name in (None, "", meshes.INERTIA_SHAPE):
        eng.mesh = None
        eng.shape = eng._shape(eng.scenario)
        eng.scene_changed = True
        return
    path = meshes.asset_path(name)  # only names the assets folder holds: no path comes from a browser
    body = meshes.scaled_to(meshes.load_mesh(path, eng.scenario.body.M), eng.scenario.body)
    sc = meshes.with_mesh(eng.scenario, body)
    previous, eng.mesh = eng.mesh, body
    try:
        eng._load(sc, label or f"mesh {name}")
    except physics.ScenarioError:
        eng.mesh = previous  # the scene stays as it was, drawn as before
        raise


# action name -> handler; ``Engine.request(name, value)`` queues one, ``tick`` applies it (``act``)
ACTIONS = {
    "play": _play, "pause": _pause, "toggle": _toggle, "step": _step, "reset": _reset, "warp": _set_warp,
    "preset": _preset, "system": _system, "fidelity": _fidelity, "accuracy": _accuracy,
    "restart_on_change": _restart_on_change, "view": _view, "overlay": _overlay, "plots": _plots,
    "polhode": _polhode, "sphere": _sphere, "mesh": _mesh, "upload": _upload, "scenario": _scenario,
    "undo": _undo, "reload": _reload,
    "compare": set_compare,  # app.engine.compare: a second run with one difference, or off
    "challenge": challenge.start, "thrust": challenge.thrust,  # app.engine.challenge: the braking race
}
# a system's own action (physics.figure.Action), by its kind
BY_KIND = {"button": _button_action, "choice": _choice_action, "item": _item_action, "view": _view_action}


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
