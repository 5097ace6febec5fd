"""A run of one's own from another engine's present: class mode's "Explore from here" (app.serve.classroom).

``branch(src)`` returns a new ``Engine`` that goes on from where ``src`` is now: the same scene (the preset it came
from, the slider values, the run-level choices, the view), the same state at the same t (the live run copied,
with its integrator's step size), and the same history, so the plots still start at t = 0. Everything is a copy:
stepping or editing the branch never touches ``src``. Compare mode's second run and the prediction overlay are
not carried (the branch starts with neither; the student turns them on again). Call it on the thread that owns
``src`` (its loop), so the copy is of one consistent moment.
"""

from __future__ import annotations

import copy
import threading

from .engine import Engine

# what makes the scene and the state (copied deeply: lists, dicts, the run, the buffers)
CARRIED = ("base", "preset", "changes", "item", "values", "fidelity_choice", "accuracy_choice", "choices",
           "view", "view_values", "show_polhode", "show_sphere", "plot_span", "playing", "restart_on_change",
           "run", "plot", "trail", "polhode", "sphere_path", "plot_all", "history", "history_columns",
           "start_scenario", "edits", "retunes", "edit_count", "shape", "world_wxyz", "K_ref", "w_ref",
           "edit_dE", "edit_note")


def branch(src: Engine) -> Engine:
    """A new engine at ``src``'s scene, state, t and history; see the module's docstring."""
    eng = Engine(src.base, mesh=src.mesh)  # a valid engine of the same scene; its own state is replaced below
    for name in CARRIED:
        value = getattr(src, name)
        lock = getattr(value, "_lock", None)  # a buffer the plots read from another thread: a lock of its own
        memo = {id(lock): threading.Lock()} if lock is not None else {}
        setattr(eng, name, copy.deepcopy(value, memo))
    eng.clock.warp = src.warp
    race = getattr(src, "challenge", None)  # not carried: the class's race is the lecturer's
    if race is not None and race.thruster is not None:  # nor a thruster the lecturer holds at this moment
        eng.run.retune(race.student(None), keep_state=True)
    eng.guard.forget(eng.scenario, eng.preset)  # undo starts here: the class's edits are not the student's
    eng.scene_changed = eng.sliders_changed = eng.plots_changed = True
    eng.prediction.restart()
    return eng


__all__ = ["CARRIED", "branch"]
