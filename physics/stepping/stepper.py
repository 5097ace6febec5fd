"""The one stepper that ``simulate`` and ``LiveRun`` both loop over.

``Stepper(model, scenario, y0)`` holds what stepping one ODE model needs: the method (the compiled DOP853
for ``"auto"``, a compiled fixed-step method RK4/RK8/midpoint with ``run.dt``), the tolerances (rtol and
atol = rtol * ATOL_FACTOR * max(1, max|y0|)), the parameter vector, the braking law's reference |G| (G0),
the step size carried from call to call, and the stiffness check's count of steps.

Contract of ``Stepper.step(y, t_out, max_steps) -> Piece``:

* **Takes** the state ``y`` at ``t_out[0]``, increasing output times ``t_out`` (at least two), and a step
  budget for this call. An adaptive call stops after ``max_steps`` accepted steps (status MAX_STEPS). A
  fixed step has no counter that stops it: the caller keeps a call within budget by asking for at most
  ``reach(max_steps)`` seconds.
* **Returns** a Piece: the raw integrator output (``Y[:n]`` the states at ``t_out[:n]``, row 0 the start;
  ``t_last``, ``y_last`` the last accepted state; ``nfev``, ``nsteps`` of this call), the ``status`` and, for a
  status that ends the run, ``what`` (the IntegrationFault text) and ``fault()``; ``rows_t``, ``rows_y``: the
  states reached after the start, the last accepted state included when it lies beyond the last output time,
  never a non-finite one (a non-finite row is dropped and the status becomes NONFINITE); ``checked``: the
  stiffness check ran in this call.
* **Guarantees**: the step size carries over (``h``): a run split into calls costs about what one call costs
  and agrees with it to the integrator's tolerance. The stepper holds no state vector (y and t are the
  caller's; it keeps only the step size and the stiffness count): two callers with the same scenario making
  the same calls get the same states, step for step (``simulate`` and ``LiveRun`` do). The same source runs
  every model: a compiled kernel (or its interpreted twin, through ``kernels``, while the compiled ones are
  being built) or a model's Python ``py_rhs`` (the interpreted twin with the model's right-hand side bound in:
  physics/kernels/py_kernels.py).
  At the end of the call in which the adaptive steps since the last check reach STIFFNESS_CHECK_STEPS
  (counted across calls, however small), the step is compared with the right-hand side's fastest rate
  (``spectral_radius``): held at DOP853's stability limit (h |lambda| > STIFF_H_LAMBDA) the run ends with
  status STIFF, since it would never finish; the rows that call reached are kept.
* **Statuses**: OK (reached ``t_out[-1]``), MAX_STEPS (out of this call's steps, not an end: go on from
  ``(t_last, y_last)``), and the ends: BRAKED (the braking law brought |G| to zero: a normal end),
  NONFINITE, UNDERFLOW (step size), MODEL_FAULT (a state the model cannot continue from), NO_CONVERGENCE
  (the implicit midpoint's iteration), STIFF.
* **Raises** nothing for what happens to the numbers while stepping: every end is a status, so a viewer
  (``LiveRun``) can show it and keep the last good state, and ``simulate`` raises ``fault()`` (an exception
  raised by a model's own Python code passes through). The constructor and ``retune`` raise
  ScenarioError, before stepping, for a method that cannot run the model on the scenario (``check_method``);
  ``step`` raises ValueError for a method it does not step (scipy's: ``solve_ivp`` runs those whole).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from physics.compiled import dispatch as kernels
from physics.compiled import dop853, fixed, midpoint
from physics.core.errors import IntegrationFault, ScenarioError
from physics.core.guarded import RightSideError, guarded
from physics.core.tolerance import ATOL_FACTOR, atol_for  # noqa: F401 - ATOL_FACTOR: simulate's public name
from physics.scenario.params import FIXED_STEP_METHODS
from physics.systems.cost import brake_and_medium  # noqa: F401 - also the stepper's public name
from physics.systems.method import method_label

# Adaptive steps between two stiffness checks, however they are split into calls (each check costs about 60
# evaluations of the right-hand side: negligible every 200 000 steps).
STIFFNESS_CHECK_STEPS = 200_000
# h |lambda| above which a step is held by stability, not accuracy: an 8th-order method resolving a mode
# to rtol <= 1e-2 needs h |lambda| under 1; DOP853's stability region reaches about 6 on the real axis
# and 4 on the imaginary one, where the step controller parks a stiff problem's step. The estimate
# below reads up to a few times high (measured: 0.43 for an accuracy-held step, 19 for a stiff one).
STIFF_H_LAMBDA = 3.0
POWER_ITERATIONS = 30  # for the Jacobian's spectral radius (finite differences of the right-hand side)

OK, BRAKED, NONFINITE, UNDERFLOW, MAX_STEPS, MODEL_FAULT = (dop853.OK, dop853.BRAKED, dop853.NONFINITE,
                                                            dop853.UNDERFLOW, dop853.MAX_STEPS, dop853.MODEL_FAULT)
NO_CONVERGENCE = midpoint.NO_CONVERGENCE
STIFF = 7
# the kernel's words name k as the model does; a message names the key (issue 24), and the text is changed here, not
# in physics/compiled/dop853.py, whose change would make numba recompile every kernel
STATUS_TEXT = {**dop853.STATUS_TEXT,
               MODEL_FAULT: dop853.STATUS_TEXT[MODEL_FAULT].replace("(k > 0)", "(pendulum.k > 0)"),
               NO_CONVERGENCE: midpoint.STATUS_TEXT, STIFF: "too stiff for the explicit integrator (DOP853)"}
GOES_ON = (OK, MAX_STEPS)  # every other status ends the run


def supports(model, sc, method: str) -> tuple[bool, str]:
    """Whether ``method`` can step ``model`` on ``sc``, and why not. DOP853, RK4, RK8 and scipy's methods step
    any ODE model. The implicit midpoint (physics/compiled/midpoint.py) is a method for one right-hand side:
    it integrates the full moving-mass kernel's equations in momentum variables (kernel id MASS_FULL), and
    only without the torques and the cavity it does not model."""
    if method != "midpoint":
        return True, ""
    b, lam = brake_and_medium(sc)
    unsupported = [name for name, present in (("a cavity", getattr(sc, "cavity", None) is not None),
                                              ("a medium", lam > 0), ("a control", b > 0)) if present]
    if model.kernel != kernels.MASS_FULL or unsupported:
        why = "the full moving-mass model" + (" without " + ", ".join(unsupported) if unsupported else "")
        return False, why if unsupported else model.name
    return True, ""


def check_method(model, sc, method: str) -> None:
    """Raise ScenarioError, naming the key, when the stepper cannot run ``model`` on ``sc`` with ``method``:
    a fixed step without run.dt, the midpoint outside what it covers (``supports``), braking on a model with
    a Python right-hand side (the braking law needs |G|, which only the compiled kernels give)."""
    if method in FIXED_STEP_METHODS and sc.run.dt is None:
        raise ScenarioError("run.dt", None, f'is required by the fixed-step method "{method}" (the largest step, s)')
    ok, has = supports(model, sc, method)
    if not ok:
        raise ScenarioError("run.method", "midpoint", f"covers only the full moving-mass model with no cavity, "
                            f'medium or control (this run has {has}); use "auto" or "RK8"')
    b, _ = brake_and_medium(sc)
    if b > 0 and model.py_rhs is not None:
        raise ScenarioError("control.b", b, f"braking needs the braking law's |G|, which {model.name} (a Python "
                            "right-hand side) does not give: use control.b = 0")


def spectral_radius(rhs, t: float, y: np.ndarray, p: np.ndarray) -> float:
    """Largest |eigenvalue| of the Jacobian of ``rhs(t, y, p, out)`` at (t, y), 1/s, by power iteration on
    finite differences (2 evaluations per iteration). Used only by the stiffness check."""
    y = np.ascontiguousarray(y, dtype=float)
    f0, f1 = np.empty_like(y), np.empty_like(y)
    rhs(t, y, p, f0)
    v = np.random.default_rng(0).standard_normal(y.size)
    v /= np.linalg.norm(v)
    eps = 1e-7 * max(1.0, float(np.linalg.norm(y)))
    radius, previous = 0.0, None
    for _ in range(POWER_ITERATIONS):
        rhs(t, y + eps * v, p, f1)
        w = (f1 - f0) / eps
        norm = float(np.linalg.norm(w))
        if not math.isfinite(norm) or norm == 0.0:
            break
        # |J v| with |v| = 1 tends to the spectral radius for a real dominant eigenvalue; for an oscillator
        # (u' = v, v' = -Omega^2 u) it alternates between Omega^2 and 1, whose geometric mean is Omega
        radius = norm if previous is None else math.sqrt(norm * previous)
        previous = norm
        v = w / norm
    return radius


@dataclass
class Piece:
    """What one ``Stepper.step`` call reached (see the module's contract)."""

    Y: np.ndarray
    n: int
    status: int
    t_last: float
    y_last: np.ndarray
    nfev: int
    nsteps: int
    rows_t: np.ndarray
    rows_y: np.ndarray
    what: str = ""
    checked: bool = False

    @property
    def ended(self) -> bool:
        return self.status not in GOES_ON

    def fault(self) -> IntegrationFault:
        """The IntegrationFault this status is (for any status but OK and BRAKED)."""
        return IntegrationFault(self.what or STATUS_TEXT[self.status], float(self.t_last))


def _identity(function):
    return function


class Stepper:
    """One ODE model stepped over a scenario; the module docstring is its contract.

    ``method``: "auto" (the compiled DOP853) or one of FIXED_STEP_METHODS (default: the scenario's
    run.method); scipy's names only for ``solve_ivp``. ``p``: the packed parameters when the caller has them.
    ``G0``: the braking law's reference |G| (None: measured from ``y0`` when braking is on). ``kernels``: applied
    to each compiled function before it is called (``physics.kernels.build.pick``: the interpreted twin
    while the compiled kernels are being built); the default calls them compiled.
    Attributes: ``h`` (the step size the next call starts with; 0: the integrator guesses), ``rtol``, ``atol``,
    ``b``, ``lam``, ``p``, ``G0``, ``unchecked`` (adaptive steps since the last stiffness check)."""

    def __init__(self, model, sc, y0, *, method: str | None = None, p=None, G0: float | None = None,
                 kernels=None):
        if model.solve is not None or (model.kernel is None and model.py_rhs is None):
            raise ValueError(f"{model.name} has no right-hand side to step")
        self.model = model
        self._pick = kernels or _identity
        self.h = 0.0
        self.unchecked = 0
        self._window_t: float | None = None  # where the steps since the last stiffness check began
        self.G0 = G0
        self._configure(sc, method, p)
        y0 = np.ascontiguousarray(y0, dtype=float)
        self.atol = atol_for(self.rtol, y0)
        if self.b > 0 and self.G0 is None:
            self.G0 = self.braking_norm(y0)

    def _configure(self, sc, method, p) -> None:
        method = method or sc.run.method
        check_method(self.model, sc, method)
        self.method = method
        self.sc = sc  # for the stiffness refusal's advice, which the model words from the scenario
        self.dt = None if sc.run.dt is None else float(sc.run.dt)
        self.p = np.asarray(self.model.pack(sc) if p is None else p, dtype=float)
        self.rtol = sc.run.rtol
        self.b, self.lam = brake_and_medium(sc)

    def retune(self, sc, y, *, method: str | None = None, p=None) -> None:
        """The scenario's parameters from now on, for the same model: p, rtol, b, lambda, method and dt change,
        atol is kept, the step size is guessed afresh, and G0 is measured at ``y`` if braking has just been
        switched on. Raises ScenarioError (before changing anything) when the method cannot run the scenario."""
        self._configure(sc, method, p)  # checks first
        self.h = 0.0  # the old step size may not suit the new parameters; let the integrator guess
        if self.b > 0 and self.G0 is None:
            self.G0 = self.braking_norm(np.ascontiguousarray(y, dtype=float))

    # ---- the model's functions, compiled, interpreted or Python ---------------------------------------
    @property
    def label(self) -> str:
        """The method's name for ``trajectory.info``, and how it runs now (compiled, the interpreted twin while
        the kernels are built, or a Python right-hand side): the name ``physics.derived`` gives too."""
        return method_label(self.model, self.method, self._pick)

    def _functions(self):
        """(dop853.integrate, fixed.run) for this model, looked up now (tests replace them on their modules)."""
        if self.model.py_rhs is not None:
            from physics.kernels.py_kernels import integrators

            return integrators(self.model)
        return self._pick(dop853.integrate), self._pick(fixed.run)

    def rhs(self, t: float, y: np.ndarray, p: np.ndarray, out: np.ndarray) -> None:
        """The model's right-hand side, ``out = dy/dt``."""
        if self.model.py_rhs is not None:
            self.model.py_rhs(t, y, p, out)
        else:
            self._pick(kernels.rhs)(self.model.kernel, t, y, p, out)

    def braking_norm(self, y: np.ndarray) -> float:
        """|G| of the braking law (1 for a model with none: a Python right-hand side cannot brake)."""
        if self.model.py_rhs is not None:
            return 1.0
        return float(self._pick(kernels.braking_norm)(self.model.kernel, y, self.p))

    def reach(self, max_steps: int) -> float:
        """The longest span (s) one call can cover in ``max_steps`` steps: max_steps * dt for a fixed step,
        inf for the adaptive method (which counts its own steps)."""
        return max_steps * self.dt if self.method in FIXED_STEP_METHODS else math.inf

    # ---- one call -----------------------------------------------------------------------------------
    def step(self, y, t_out, max_steps: int) -> Piece:
        """Integrate from ``y`` at ``t_out[0]`` onto ``t_out``; see the module docstring for the contract."""
        y = np.ascontiguousarray(y, dtype=float)
        t_out = np.ascontiguousarray(t_out, dtype=float)
        if self._window_t is None:
            self._window_t = float(t_out[0])
        G0 = 1.0 if self.G0 is None else self.G0
        what, checked = "", False
        if self.method == "midpoint":
            Y, n, status, t_last, y_last, nfev, nsteps = self._pick(midpoint.integrate)(y, self.p, t_out, self.dt)
            h = self.dt
        elif self.method in FIXED_STEP_METHODS:
            run = self._functions()[1]
            Y, n, status, t_last, y_last, nfev, nsteps = run(fixed.TABLEAUS[self.method], self.model.kernel, y,
                                                             self.p, t_out, self.dt, self.b, self.lam, G0)
            h = self.dt
            if status == NONFINITE:  # a fixed step beyond the method's stability limit, most likely
                what = (f"{self.method} with dt = {self.dt:g} s: state became non-finite (NaN or infinity); the "
                        "step is beyond the method's stability limit for this problem (stiff): use a smaller "
                        "run.dt or an adaptive method")
        elif self.method == "auto":
            integrate = self._functions()[0]
            Y, n, status, t_last, y_last, nfev, nsteps, h = integrate(
                self.model.kernel, y, self.p, t_out, self.rtol, self.atol, self.b, self.lam, int(max_steps), self.h,
                G0)
        else:
            raise ValueError(f"the stepper steps auto and {', '.join(FIXED_STEP_METHODS)}, not {self.method!r}")
        t_last = float(t_last)
        if status in GOES_ON:
            self.h = float(h)
            if self.method == "auto":
                self.unchecked += int(nsteps)
                if self.unchecked >= STIFFNESS_CHECK_STEPS:
                    checked = True
                    status, what = self._stiffness(t_last, y_last, status)
        rows_t, rows_y = t_out[1:n], Y[1:n]
        if t_last > (rows_t[-1] if len(rows_t) else t_out[0]):  # the last accepted state, at its own time
            rows_t, rows_y = np.append(rows_t, t_last), np.vstack([rows_y, y_last[None, :]])
        good = np.all(np.isfinite(rows_y), axis=1)
        if not np.all(good):  # never hand on a non-finite state
            rows_t, rows_y = rows_t[good], rows_y[good]
            if status in GOES_ON or status == BRAKED:
                status, what = NONFINITE, ""
        return Piece(Y, int(n), int(status), t_last, y_last, int(nfev), int(nsteps), rows_t, rows_y, what, checked)

    def _stiffness(self, t_last: float, y_last: np.ndarray, status: int) -> tuple[int, str]:
        """The stiffness check over the steps since the last one: (STIFF, why) when the step is held at the
        stability limit, else (status, "")."""
        steps, since = self.unchecked, self._window_t
        self.unchecked, self._window_t = 0, t_last
        why = self._held(t_last, y_last, steps, t_last - since)
        return (STIFF, why) if why else (status, "")

    def stiff_short_of(self, t_last: float, y_last: np.ndarray, steps: int, span: float, t_goal: float,
                       steps_left: int) -> str:
        """The STIFF text when, after ``steps`` steps covering ``span`` s, the step is held at the stability
        limit and t_goal lies more than ``steps_left`` such steps beyond ``t_last``: the call would run out of
        steps there, and the check at its end would say so. '' otherwise (the usual check still comes)."""
        if not self.h > 0 or not (t_goal - t_last) / self.h > steps_left:
            return ""
        return self._held(t_last, y_last, steps, span)

    def _held(self, t_last: float, y_last: np.ndarray, steps: int, span: float) -> str:
        """The STIFF text when the step at (t_last, y_last) is held at the stability limit (h |lambda| >
        STIFF_H_LAMBDA), naming the ``steps`` steps that covered ``span`` s; '' when it is held by accuracy."""
        h_lambda = self.h * spectral_radius(self.rhs, t_last, y_last, self.p)
        if h_lambda <= STIFF_H_LAMBDA:
            return ""
        advice = (self.model.stiff_advice(self.sc) if self.model.stiff_advice is not None else
                  "the internal part's fastest rate sets the step: slow it, or use a cheaper fidelity")
        return (f"too stiff for the explicit integrator (DOP853): {steps} steps covered {span:.3g} s at its "
                f"stability limit (h |lambda| = {h_lambda:.2g}); {advice}")

    # ---- scipy's methods: whole runs (simulate only) ---------------------------------------------------
    def solve_ivp(self, y0, t: np.ndarray, method: str, max_evals: int, progress=None):
        """scipy's solve_ivp with ``method`` on the model's right-hand side over the output times ``t`` (the
        speed study's baselines). Returns (Y, t_out, info). Raises IntegrationFault beyond ``max_evals``
        evaluations of the right-hand side (scipy has no step budget of its own) or when scipy fails."""
        from scipy.integrate import solve_ivp  # here: importing scipy.integrate costs the explorer's start 0.4 s

        p = self.p
        out = np.empty_like(np.asarray(y0, dtype=float))
        evaluations = 0

        def fun(tt, y):
            nonlocal evaluations
            evaluations += 1
            if progress and evaluations % 1000 == 0:
                progress(min(1.0, (tt - t[0]) / (t[-1] - t[0])))
            self.rhs(tt, y, p, out)
            return out.copy()

        events = None
        if self.b > 0:
            G0 = self.braking_norm(y0)

            def brake(tt, y):
                return self.braking_norm(y) - 1e-9 * G0

            brake.terminal = True
            events = brake
        try:
            # guarded: scipy has no step budget, and would reject steps with a NaN error norm, then blame the step size
            sol = solve_ivp(guarded(fun, max_evals, f"scipy {method}"), (t[0], t[-1]), y0, method=method, t_eval=t,
                            rtol=self.rtol, atol=self.atol, events=events)
        except RightSideError as stop:
            why = (f"more than {max_evals} evaluations of the right-hand side (the budget of a run); use method "
                   '"auto"' if stop.over_budget else STATUS_TEXT[NONFINITE].replace("state", "the right-hand side"))
            raise IntegrationFault(f"scipy {method}: {why}", stop.t) from None
        if sol.status == -1:  # scipy's own words, but for the one failure the compiled steppers name too
            why = STATUS_TEXT[UNDERFLOW] if "spacing between numbers" in sol.message else sol.message
            ts = np.asarray(sol.t)  # scipy leaves t a list where it failed before the first output time
            raise IntegrationFault(f"{method}: {why}", float(ts[-1]) if ts.size else float(t[0]))
        Y, t_out = sol.y.T, sol.t
        reason = STATUS_TEXT[OK]
        if sol.status == 1:
            t_out, Y = np.append(t_out, sol.t_events[0][0]), np.vstack([Y, sol.y_events[0][0]])
            reason = STATUS_TEXT[BRAKED]
        return Y, t_out, dict(method=method_label(self.model, method, self._pick), nfev=int(sol.nfev),
                              steps=getattr(sol, "nsteps", None), stop_reason=reason, t_stop=float(t_out[-1]))
