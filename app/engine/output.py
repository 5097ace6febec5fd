"""What a tab reads out and exports: the plots' data, the readouts and their details, the trajectory as CSV
as functions of what they read. ``app.engine.engine.Engine``'s methods of the same names
call them; the panel and the download buttons call those (the CSV on viser's thread: the stores it reads are
locked)."""

from __future__ import annotations

import io

import numpy as np

from physics import qmul

from . import words
from .buffers import HISTORY_ROWS, SAMPLES_PER_FRAME
from .edit_report import edit_readouts


def plot_data(rows: np.ndarray, overlay: tuple[np.ndarray, np.ndarray] | None) -> tuple[np.ndarray, ...]:
    """(t, theta, overlay's theta, |K|, E) of the plot rows ``rows`` (t, theta, |K|, E). The overlay predicts
    from t = 0; where it has no value yet (a run that has gone past the prediction, until the next one is
    ready) and without an overlay it is theta (the plot hides it). No NaN: uPlot's auto-range would break on
    them. One row (a run stopped at its start) comes as that row twice: the charts draw nothing of fewer than two,
    and kept showing the scene before it."""
    if len(rows) == 1:
        rows = np.repeat(rows, 2, axis=0)
    t = rows[:, 0]
    over = rows[:, 1].copy()
    if overlay is not None and len(t):
        ot, oth = overlay
        inside = (t >= ot[0]) & (t <= ot[-1])
        over[inside] = np.interp(t[inside], ot, oth)
    return t, rows[:, 1], over, rows[:, 2], rows[:, 3]


def readouts(run, world_wxyz: np.ndarray, edit_dE: float | None, edit_note: str) -> dict[str, str]:
    """What the panel shows, ``name -> value`` (app.engine.words says why each is worded so): the run's
    (physics.LiveRun) last state, its attitude in the view whose K of t = 0 points up (``world_wxyz``), and
    what the last edit did (``edit_dE``, ``edit_note``)."""
    d = {"t": f"{run.t:.4g} s", "theta": f"{run.last.theta[0]:.6f} rad", "|K|": f"{run.last.K[0]:.6g} kg m^2/s",
         "E": f"{run.last.E[0]:.6g} J"}
    d.update(words.braking_words(run.t, run.remaining_braking_time()))
    d["fidelity"] = words.fidelity_words(run.fidelity, run.requested == "auto")
    psi, _, phi = words.euler_angles(qmul(world_wxyz, run.last.quat[0]))
    d["precession psi"] = f"{psi:.4f} rad"
    d["spin phi"] = f"{phi:.4f} rad"
    d.update(edit_readouts(edit_dE, edit_note, float(run.last.E[0])))
    return d


END_PENDING = "being worked out"  # the engine's end state while its background thread works it out


def end_readouts(end, E_now: float) -> dict[str, str]:
    """The energy still to lose before the end state (physics.EndState): E now minus E_end; "none" when the
    scene has no fixed end (braking, a medium, no dissipation: the Details say which)."""
    if not end:
        pending = end.reason == END_PENDING
        return {"energy still to lose": "working it out..." if pending else "none (no fixed end state)"}
    return {"energy still to lose": f"{max(E_now - end.E_end, 0.0):.6g} J", "E_end": f"{end.E_end:.6g} J"}


def end_details(end) -> dict[str, str]:
    """The end state in words: the final spin and its axis in body axes, or why there is none."""
    if not end:
        return {"end state": end.reason}
    axis = ", ".join(f"{x:.4f}" for x in end.axis)
    more = "" if end.axis_fixed else " (or any axis of the plane of largest moment)"
    sign = "" if end.sign_fixed else " (or its opposite)"
    return {"end state": f"spin {end.spin:.6g} rad/s about [{axis}]{sign}{more} in body axes, I_max = "
                         f"{end.I_max:.6g} kg m^2"}


def details(run) -> dict[str, str]:
    """The technical side of the readouts, for the Details folder: the model and the raw attitude."""
    q = run.last.quat[0]
    return {"model": run.model.name, "method": str(run.scenario.run.method),
            "q (body to inertial, w x y z)": "[" + ", ".join(f"{x:.4f}" for x in q) + "]"}


def csv(history, columns: tuple[str, ...], preset: str, t: float, edits: str) -> bytes:
    """The run from t = 0 (``history``, an app.engine.history.DecimatingStore of rows named ``columns``): "#"
    lines saying what the rows are (all samples, or every n-th of them, and the changes the run went on
    through, ``edits``), then the column names (t,theta,K,E,...) and the rows."""
    rows, stride = history.snapshot()  # a download's callback thread reads while the loop appends
    buf = io.StringIO()
    kept = ("every sample kept" if stride == 1 else
            f"rows decimated: every {_ordinal(stride)} sample kept, and the last one "
            f"(at most {HISTORY_ROWS} rows from t = 0)")
    buf.write(f"# Quasirigid explorer, {preset}: t = 0 to {t:.9g} s, {len(rows)} rows, "
              f"{kept}; {SAMPLES_PER_FRAME} samples per frame played\n")
    if edits:
        buf.write(f"# {edits}\n")
    buf.write(",".join(columns) + "\n")
    # repr: the shortest text that reads back to the same double, 4x faster than savetxt's "%.17g" (0.26 s
    # for 20,000 rows of 19 columns), which matters as the download runs on a thread sharing the GIL
    buf.writelines(",".join(map(repr, row)) + "\n" for row in rows.tolist())
    return buf.getvalue().encode()


def edits_text(edits: list[tuple[float, str]], edit_count: int) -> str:
    """The changes the run went on through since t = 0 (the first ``edits``, (t, what), of ``edit_count``;
    "" when none)."""
    if not edits:
        return ""
    shown = "; ".join(f"t = {t:.4g} s: {what}" for t, what in edits)
    more = edit_count - len(edits)
    return f"edited since t = 0 ({shown}" + (f"; and {more} more" if more > 0 else "") + ")"


def _ordinal(n: int) -> str:
    suffix = "th" if n % 100 in (11, 12, 13) else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"
