"""The engine's background workers: the cheaper fidelity's prediction (the overlay) and auto's badge.
Each runs in a daemon thread, so a long computation never stalls the frames; a newer request makes an
older overlay give up, and the badge is worked out once per scenario.

Mixed into ``app.engine.Engine``: they read its ``scenario``, ``run`` and ``plot_window()`` and set its
``overlay``, ``error`` and ``plots_changed``.
"""

from __future__ import annotations

import threading
import warnings

import numpy as np

import physics

OVERLAY_SAMPLES = 600
OVERLAY_WINDOWS = 2.0  # a prediction covers this many plot windows ahead


class OverlayMixin:
    """The overlay: ``overlay`` is (t, theta) or None; ``overlay_fidelity`` "none", "averaged" or "closed"."""

    def _init_overlay(self) -> None:
        self.overlay_fidelity = "none"
        self.overlay = None
        self.overlay_dirty = True
        self._overlay_thread: threading.Thread | None = None
        self._overlay_gen = 0

    def _compute_overlay(self) -> None:
        """Start computing the cheaper fidelity's prediction in a background thread: a long prediction must
        not stall the frames. A newer request cancels an older one.

        Moving mass: the averaged model or the closed form from the present state (G and theta of now).
        Spherical pendulum: its averaged model from t = 0 (it needs the pendulum's initial state).
        Both pendulum systems, "closed": linear theory's envelope theta0 exp(-rate t) (MODELS B.4)."""
        if self._overlay_thread is not None and self._overlay_thread.is_alive():
            self._overlay_gen += 1  # cancel it; overlay_dirty stays set, so a later tick starts anew
            return
        self.overlay_dirty = False
        self.overlay = None
        self._overlay_gen += 1
        self.plots_changed = True
        fid = self.overlay_fidelity
        if fid == "none":
            return
        sc = self.scenario
        t0 = self.run.t
        horizon = max(OVERLAY_WINDOWS * self.plot_window(), 1.0)  # recomputed when the run passes its end
        try:
            if sc.system != "moving_mass":
                if fid == "closed":
                    d = physics.derived(sc)
                    t = np.linspace(0.0, t0 + horizon, OVERLAY_SAMPLES)
                    self.overlay = (t, d["theta0"] * np.exp(-float(d["decay_rate_linear"]) * t))
                    return
                t0, horizon = 0.0, t0 + horizon
            elif t0 > 0:  # predict from the present state: G0 and theta0 of now
                sc = sc.with_values(**{"initial.G0": float(self.run.last.K[0]),
                                       "initial.theta0": float(self.run.last.theta[0])})
            sc = sc.with_values(**{"run.t_end": horizon, "run.samples": OVERLAY_SAMPLES})
        except (physics.ScenarioError, ValueError) as exc:
            self.error = f"overlay ({fid}): {exc}"
            return
        gen = self._overlay_gen

        def progress(_fraction):
            if gen != self._overlay_gen:  # chunks between compiled calls: the place to give up
                raise _Cancelled

        def work():
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", physics.ValidityWarning)
                    tr = physics.simulate(sc, fidelity=fid, progress=progress)
            except _Cancelled:
                return
            except (physics.ScenarioError, physics.IntegrationFault, ValueError) as exc:
                if gen == self._overlay_gen:
                    self.error = f"overlay ({fid}): {exc}"
                return
            if gen == self._overlay_gen:
                self.overlay = (t0 + tr.t, tr.theta)
                self.plots_changed = True

        self._overlay_thread = threading.Thread(target=work, name="overlay", daemon=True)
        self._overlay_thread.start()

    def wait_overlay(self, timeout: float = 30.0) -> bool:
        """Block until the overlay being computed is done (for tests and scripts)."""
        if self._overlay_thread is not None:
            self._overlay_thread.join(timeout)
        return self.overlay is not None

    @property
    def has_overlay(self) -> bool:
        return self.overlay is not None


class BadgeMixin:
    """Auto's badge, cached per scenario: ``badge()`` returns markdown at once (a placeholder until ready)."""

    def _init_badge(self) -> None:
        self._badge: tuple | None = None  # (scenario, markdown) of the last badge
        self._badge_busy = False

    def badge(self, block: bool = False) -> str:
        """Auto's choice (model, method, error bound against the requested accuracy, and why) and the
        averaged model's validity conditions, as markdown. Computed once per scenario, in a background
        thread (up to 0.4 s for three plane pendulums: the frames go on meanwhile); until it is ready,
        a placeholder. ``block``: wait for it instead."""
        sc = self.scenario
        done = self._badge
        if done is not None and done[0] is sc:
            return done[1]
        if block:
            self._badge = (sc, _badge_text(sc))
            return self._badge[1]
        with self._lock:
            start = not self._badge_busy
            self._badge_busy = True
        if start:
            threading.Thread(target=self._badge_worker, args=(sc,), name="badge", daemon=True).start()
        return "_auto: working out its choice..._"

    def _badge_worker(self, sc: physics.Scenario) -> None:
        try:
            self._badge = (sc, _badge_text(sc))
        finally:
            self._badge_busy = False  # the next call starts another if the scenario has changed since


class _Cancelled(Exception):
    """A newer overlay request replaced this one."""


def _badge_text(sc: physics.Scenario) -> str:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            d = physics.derived(sc)
            conds = physics.validity_conditions(sc)
    except Exception as exc:  # never let the badge break a frame
        return f"auto: unavailable ({exc})"
    head = f"**auto → {d['auto_fidelity']}** · {d.get('auto_method', '')}"
    if conds:
        head += f"  \naveraged model's conditions {'hold' if all(c.holds for c in conds) else 'fail'}:"
    lines = [f"{'OK' if c.holds else 'FAILS'}: {c}" for c in conds]
    bound = d.get("auto_error_bound")
    shown_bound = isinstance(bound, float) and bound > 0
    lines.append(f"requested accuracy: {d.get('auto_accuracy', 'not set')}"
                 + (f"; error bound of the choice {bound:.2g} rad" if shown_bound else ""))
    return head + "  \n" + "  \n".join(lines) + f"  \n_{d['auto_reason']}_"
