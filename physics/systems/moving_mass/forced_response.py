"""The full model's slow motion, predicted from the mass's steady forced motion (issue 23): what the averaged
model leaves out, so that the error estimate can say how far the cheaper theta is from the full model's instead
of bounding a scatter.

Along the free body's nutation the mass is driven at the nutation frequency nu. Seen from axes turning with
w_perp about e3 the forcing is constant, so the mass's steady motion is a constant displacement v there, the root
of one 3x3 linear system with every rotating-frame term kept (centrifugal softening, Coriolis, Euler, the reduced
mass): first order in m, all orders in eps, where the averaged model keeps u = -a/Omega^2 + chi a'/Omega^4. nu
itself is the one the averaged equations' conservative F term gives, -(d + F G^2/A) w3 (seed 004 eq. (1)): that
shift is relative O(m rho^2 eps^2 / (A d)), small in m, but it moves the dissipation by twice as much and
matters next to a near-sphere's small d. From v follow, by the full model's own formulas (docs/models.md A.2),
the total angular momentum K, the energy E and the power P the damper takes, as functions of (|J* w|, theta_G).
The energy balance and the external torque M then move them:

    E' = w.M - P,      |K|' = (K/|K|).M,

two equations for the rates of (|J* w|, theta_G); with no medium and no brake |K| is fixed and this is
theta_K' = -P / (dE/dtheta_K). theta_K, the nutation angle of K that the full model reports, is read off the same
steady motion. A cavity adds its Stokes dissipation at the same nu and its fluid's angular momentum to K.

Quadratic friction, -m lam_q |u'| u', is exact here too: along the steady motion |u'| is constant, so it acts as a
viscous chi + lam_q |u'|, and |u'| is solved for (``_damped``).

A mass that starts at rest first sheds a free oscillation, which moves theta_K by a jump the steady motion does not
know: the full model itself is run over that transient (TRANSIENT_DECAYS of the mass's decay times: cheap, some
1500 steps at most inside the estimate's domain), and the prediction starts where it ends.
Measured against the full model on the study's scenarios (docs/models.md A.5), theta_K(t) follows the full model
to a few per cent of the cheaper model's error.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline, RectBivariateSpline

from physics.compiled import dop853
from physics.core.guarded import RightSideError, guarded
from physics.core.tolerance import atol_for
from physics.registry import get_model
from physics.scenario.scenario import Scenario
from physics.systems.moving_mass.coefficients import coefficients

TABLE = 161  # theta_G points of the rate table the slow motion is integrated on
TABLE_G = 25  # |J* w| points of that table where a medium or a brake changes it
NEWTON = 5  # rounds that scale |J* w| so that |K| is the run's (the mass adds O(m eps^2) to it)
DIFF = 1e-5  # the central differences' step: relative in |J* w|, rad in theta_G
TRANSIENT_DECAYS = 12.0  # a mass at rest: the full model runs this many of its free oscillation's decay times
TRANSIENT_STEPS = 200_000  # ... within this many steps (the estimate's domain, chi/Omega >= 0.2, keeps it to ~1500)
TRANSIENT_SAMPLES = 257
# right-hand sides a prediction's slow integration may take (a few seconds): the shipped scenes take 44-7000, the
# slowest over t_end = 1e-300 .. 1e100 s on oblate_settling ~7000 (tests/test_forced_response.py)
MAX_CALLS = 200_000
RTOL = 1e-10  # the study's own tolerance for the full model
QUADRATIC_BRACKET = 60  # doublings at most of the bracket of quadratic friction's steady speed
QUADRATIC_ROUNDS = 60  # Newton's (or bisection's) steps at most towards that speed
QUADRATIC_RTOL = 1e-14  # ... until it is this close, relative: well below the central differences' step (DIFF)
E3 = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])  # e3 x
UNIT3 = np.array([0.0, 0.0, 1.0])


def applies(sc: Scenario) -> bool:
    """A symmetric body and a damped mass (viscous, quadratic friction or both), braked, if at all, along K or
    J* w."""
    ms = sc.mass
    return (ms is not None and (ms.chi > 0 or ms.lam_q > 0) and sc.body.A == sc.body.B
            and (sc.control is None or sc.control.b == 0 or sc.control.law in ("K", "Jw")))


def _lam(sc: Scenario) -> float:
    return 0.0 if sc.medium is None else float(sc.medium.lambda_)


def _b(sc: Scenario) -> float:
    return 0.0 if sc.control is None else float(sc.control.b)


def _skew(a: np.ndarray) -> np.ndarray:
    out = np.zeros((a.shape[0], 3, 3))
    out[:, 0, 1], out[:, 0, 2], out[:, 1, 2] = -a[:, 2], a[:, 1], -a[:, 0]
    out[:, 1, 0], out[:, 2, 0], out[:, 2, 1] = a[:, 2], -a[:, 1], a[:, 0]
    return out


def steady(sc: Scenario, g: np.ndarray, th: np.ndarray) -> dict[str, np.ndarray]:
    """The steady forced motion where J* w = g (sin th, 0, cos th), arrays of one shape: |K|, theta_K, E, the power
    P the damper and cavity take, the external torque's w.M and (K/|K|).M, and the mass's displacement v (rows, in
    axes turning with w_perp about e3)."""
    g, th = np.broadcast_arrays(np.asarray(g, dtype=float).ravel(), np.asarray(th, dtype=float).ravel())
    A, C, M = sc.body.A, sc.body.C, sc.body.M
    ms = sc.mass
    m, rho, O2 = ms.m, ms.rho, ms.Omega**2
    eta = m / M
    mr = m * (1.0 - eta)
    W = np.stack([g * np.sin(th) / A, np.zeros(g.size), g * np.cos(th) / C], axis=1)
    nu = -((1.0 - C / A) + m * rho * rho * C * g * g / (O2 * A**4)) * W[:, 2]
    dW = nu[:, None] * np.cross(UNIT3, W)
    Wx = _skew(W)
    rotating = (nu * nu)[:, None, None] * (E3 @ E3) + 2.0 * nu[:, None, None] * (Wx @ E3) + _skew(dW) + Wx @ Wx
    r = np.broadcast_to(rho * UNIT3, W.shape)
    chi, v, du = _damped(sc, (1.0 - eta) * rotating + O2 * np.eye(3), nu,
                         -(np.cross(dW, r) + np.cross(W, np.cross(W, r)))[:, :, None])
    d = r / (1.0 - eta) + v
    vel = np.cross(W, d) + du
    Jb = np.array([A, A, C]) - m * rho * rho / (1.0 - eta) * np.array([1.0, 1.0, 0.0])
    K = Jb * W + mr * np.cross(d, vel)
    E = 0.5 * np.sum(Jb * W * W, axis=1) + 0.5 * mr * np.sum(vel * vel, axis=1) + 0.5 * m * O2 * np.sum(v * v, axis=1)
    P = m * chi * np.sum(du * du, axis=1)
    if sc.cavity is not None:
        # the fluid carries k_f = -cav f(w), f the free body's Euler acceleration (A.2), and its torque
        # -(k_f' + w x k_f) does work cav w.Df(w) w'; along the nutation, w' = nu e3 x w, that is -cav nu w1^2 w3
        # (C - A)/A: linear in the shifted nu, where cav nu^2 w1^2 overstated it by the shift (twice a near-sphere's
        # rate error, seen on a cavity-dominated prolate body). The slow drift of w adds O(cav theta'/nu) to it,
        # which no case measured could see
        cav = float(sc.cavity.coupling)
        K = K + cav * ((1.0 - C / A) * W[:, 2])[:, None] * np.cross(UNIT3, W)
        P = P + cav * nu * W[:, 0] ** 2 * W[:, 2] * (C - A) / A
    Kn = np.linalg.norm(K, axis=1)
    Khat = K / np.where(Kn > 0, Kn, 1.0)[:, None]
    Jw = np.array([A, A, C]) * W
    lam, b = _lam(sc), _b(sc)
    brake = Khat if sc.control is None or sc.control.law == "K" else Jw / np.where(g > 0, g, 1.0)[:, None]
    torque = -lam * Jw - b * brake
    return dict(K=Kn, thK=np.arctan2(np.hypot(K[:, 0], K[:, 1]), K[:, 2]), E=E, P=P,
                wM=np.sum(W * torque, axis=1), KM=np.sum(Khat * torque, axis=1), v=v, chi=chi)


def _damped(sc: Scenario, undamped: np.ndarray, nu: np.ndarray, force: np.ndarray):
    """(chi, v, du): the damping the steady motion sees, its displacement and its velocity, for the matrix
    ``undamped`` and the forcing ``force`` (n, 3, 1). The mass's damping force is -m (chi + lam_q |u'|) u', and in
    the steady motion |u'| = |du| is constant (v turns with w_perp about e3), so quadratic friction is exactly a
    viscous chi + lam_q |du|, with |du| the root s of |du(chi + lam_q s)| = s: Newton's method on it (|du|'s
    derivative in chi from the same matrix), kept inside a bracket of the root and bisecting where a step leaves it."""
    ms = sc.mass
    gyro = nu[:, None, None] * E3

    def solve(chi):
        mat = undamped + chi[:, None, None] * gyro
        v = np.linalg.solve(mat, force)[:, :, 0]
        return mat, v, nu[:, None] * np.cross(UNIT3, v)

    chi = np.full(nu.shape, float(ms.chi))
    if ms.lam_q == 0:
        return (chi, *solve(chi)[1:])
    lo, hi = np.zeros(nu.shape), np.linalg.norm(solve(chi)[2], axis=1)
    for _ in range(QUADRATIC_BRACKET):  # |du| need not fall as the damping grows (the gyroscopic terms)
        short = np.linalg.norm(solve(chi + ms.lam_q * hi)[2], axis=1) > hi
        if not short.any():
            break
        hi = np.where(short, 2.0 * hi, hi)
    s = 0.5 * (lo + hi)
    for _ in range(QUADRATIC_ROUNDS):
        mat, v, du = solve(chi + ms.lam_q * s)
        speed = np.linalg.norm(du, axis=1)
        f = speed - s
        if np.all(np.abs(f) <= QUADRATIC_RTOL * hi):
            break
        lo, hi = np.where(f > 0, s, lo), np.where(f > 0, hi, s)
        dv = -np.linalg.solve(mat, gyro @ v[:, :, None])[:, :, 0]  # dv/dchi
        slope = ms.lam_q * np.sum(du * nu[:, None] * np.cross(UNIT3, dv), axis=1) / np.where(speed > 0, speed, 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = s - f / (slope - 1.0)
        s = np.where((step >= lo) & (step <= hi), step, 0.5 * (lo + hi))
    else:  # out of rounds: the motion at the last step taken
        _, v, du = solve(chi + ms.lam_q * s)
    return chi + ms.lam_q * s, v, du


def at_K(sc: Scenario, th: np.ndarray, K: float) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(|J* w|, the steady motion) at theta_G = th with |K| = K."""
    g = np.full(np.shape(th), K, dtype=float)
    for _ in range(NEWTON):
        g = g * K / steady(sc, g, th)["K"]
    return g, steady(sc, g, th)


def rates(sc: Scenario, g: np.ndarray, th: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(theta_K, |J* w|', theta_G') at (g, th): E' = w.M - P and |K|' = (K/|K|).M solved for the two rates by the
    central differences of E and |K| (with no torque |K|' = 0, and this is theta_G' = -P / (dE/dtheta_G))."""
    g, th = np.broadcast_arrays(np.asarray(g, dtype=float).ravel(), np.asarray(th, dtype=float).ravel())
    hg, ht = DIFF * g, np.full(g.shape, DIFF)
    s = steady(sc, g, th)
    gp, gm, tp, tm = (steady(sc, g + hg, th), steady(sc, g - hg, th), steady(sc, g, th + ht), steady(sc, g, th - ht))
    Eg, Et = (gp["E"] - gm["E"]) / (2 * hg), (tp["E"] - tm["E"]) / (2 * ht)
    Kg, Kt = (gp["K"] - gm["K"]) / (2 * hg), (tp["K"] - tm["K"]) / (2 * ht)
    dE, dK = s["wM"] - s["P"], s["KM"]
    det = Eg * Kt - Et * Kg
    return s["thK"], (dE * Kt - Et * dK) / det, (Eg * dK - Kg * dE) / det


def transient_time(sc: Scenario) -> float:
    """s: TRANSIENT_DECAYS of the slowest decay of the mass's free oscillation, (1 - eta) u'' + chi u' + Omega^2 u
    = 0. Quadratic friction damps a small oscillation about the steady motion at least as a viscous lam_q |du|
    would (|du| the steady speed at the start); a larger one faster."""
    ms = sc.mass
    a = 1.0 - ms.m / sc.body.M
    chi = ms.chi
    if ms.lam_q > 0:
        co = coefficients(sc)
        chi = float(steady(sc, np.array([co.G0]), np.array([co.theta0]))["chi"][0])
    disc = chi * chi - 4.0 * a * ms.Omega**2
    slowest = chi / (2.0 * a) if disc < 0 else (chi - math.sqrt(disc)) / (2.0 * a)
    return TRANSIENT_DECAYS / slowest


def _full_start(sc: Scenario):
    full = get_model("moving_mass", "full")
    p = full.pack(sc)
    return full, p, np.asarray(full.initial_state(sc, p), dtype=float)


def full_start(sc: Scenario) -> tuple[float, float]:
    """(|K|, theta_K) of the full model's initial state."""
    full, p, y0 = _full_start(sc)
    tr = full.observe(np.zeros(1), y0[None, :], p, sc)
    return float(tr.K[0]), float(tr.theta[0])


def _transient(sc: Scenario, t_end: float) -> tuple[np.ndarray, np.ndarray, float] | None:
    """(t, theta_K, |K| at the end) of the full model over [0, t_end], or None where it does not finish within
    TRANSIENT_STEPS (or the brake stops the body first)."""
    full, p, y0 = _full_start(sc)
    t = np.linspace(0.0, t_end, TRANSIENT_SAMPLES)
    G0 = float(np.linalg.norm(np.array([sc.body.A, sc.body.A, sc.body.C]) * y0[:3]))
    Y, n, *_ = dop853.integrate(full.kernel, y0, p, t, RTOL, atol_for(RTOL, y0), _b(sc), _lam(sc), TRANSIENT_STEPS,
                                0.0, G0)
    if n < t.size:
        return None
    tr = full.observe(t, Y, p, sc)
    return t, np.asarray(tr.theta), float(tr.K[-1])


def _grid(th0: float, cheap_theta: np.ndarray) -> np.ndarray:
    """theta_G points over the cheaper path's range and a margin, on theta0's side of pi/2."""
    lo, hi = min(th0, float(np.min(cheap_theta))), max(th0, float(np.max(cheap_theta)))
    pad = 0.2 * (hi - lo) + 0.02
    half = math.pi / 2
    side = (1e-6, half - 1e-6) if th0 < half else (half + 1e-6, math.pi - 1e-6)
    return np.linspace(max(side[0], lo - pad), min(side[1], hi + pad), TABLE)


def predicted_theta(sc: Scenario, t: np.ndarray, cheap_theta: np.ndarray, cheap_G: np.ndarray) -> np.ndarray | None:
    """theta_K at times ``t`` (from 0) as the full model is predicted to run; None where this does not apply
    (``applies``), NaN where it cannot be made (a transient past TRANSIENT_STEPS, an integration that fails). The
    cheaper model's theta and |G| at ``t`` set the range of the rate table. Past the point where a brake has taken
    |G| below the table, theta_K stays where it was (its rates vanish with |G|)."""
    out = _predicted(sc, t, cheap_theta, cheap_G)
    return None if out is None else out[0]


def predicted_gap(sc: Scenario, t: np.ndarray, cheap_theta: np.ndarray, cheap_G: np.ndarray) -> float | None:
    """max |theta_K - theta_cheap| as predicted, over ``t`` and, for a mass at rest, over the full model's own
    samples of its transient too (its wobble peaks between the path's times); None where this does not apply, NaN
    where it cannot be made."""
    out = _predicted(sc, t, cheap_theta, cheap_G)
    if out is None:
        return None
    theta, early = out
    gap = float(np.max(np.abs(theta - cheap_theta)))
    if early is not None:
        gap = max(gap, float(np.max(np.abs(early[1] - np.interp(early[0], t, cheap_theta)))))
    return gap


def _predicted(sc: Scenario, t: np.ndarray, cheap_theta: np.ndarray, cheap_G: np.ndarray):
    """(theta_K at t, the transient's (t, theta_K) or None), or None where this does not apply."""
    if not applies(sc):
        return None
    t = np.asarray(t, dtype=float)
    t0, early = 0.0, None
    if sc.initial.mass_state == "quasistatic":
        K, thK0 = full_start(sc)
    else:
        # a mass at rest: the full model over its transient, then the steady motion from where it ends
        t0 = min(transient_time(sc), float(t[-1]))
        run = _transient(sc, t0)
        if run is None:
            return np.full(t.shape, np.nan), None
        tt, th, K = run
        thK0, early = float(th[-1]), (tt, th)
        if t0 >= t[-1]:
            return np.interp(t, *early), early
    grid = _grid(thK0, cheap_theta)
    g_line, s_line = at_K(sc, grid, K)
    order = np.argsort(s_line["thK"])
    thG0 = float(np.interp(thK0, s_line["thK"][order], grid[order]))
    g0 = float(np.interp(thG0, grid, g_line))
    later = t >= t0
    out = np.empty_like(t)
    if _lam(sc) == 0 and _b(sc) == 0:
        _, _, rate = rates(sc, g_line, grid)
        spline = CubicSpline(grid, rate)  # smooth: a piecewise-linear rate makes the integrator crawl at its kinks
        slope = spline.derivative()
        # implicit (Radau), not explicit: once theta_G has settled at the rate's zero the equation is stiff, and an
        # explicit method's steps stop growing at its stability limit, so the cost grew with t_end without bound
        # (t_end = 1e15 s on oblate_settling ran for minutes inside auto's choice). Not LSODA: it never returned on
        # a horizon of 1e-300 s. The cap is the bound for whatever input still finds a way to crawl
        try:
            sol = solve_ivp(guarded(lambda _s, y: spline(y), MAX_CALLS, "the predicted slow motion"),
                            (t0, float(t[-1])), [thG0], t_eval=t[later], rtol=1e-10, atol=1e-12, method="Radau",
                            jac=lambda _s, y: [[float(slope(y[0]))]])
        except RightSideError:
            return np.full(t.shape, np.nan), None
        if not sol.success:
            return np.full(t.shape, np.nan), None
        out[later] = np.interp(sol.y[0], grid, s_line["thK"])
    else:
        out[later] = _varying_K(sc, t[later], t0, g0, thG0, grid, cheap_G)
    if early is not None:
        out[~later] = np.interp(t[~later], *early)
    return out, early


def _varying_K(sc: Scenario, t: np.ndarray, t0: float, g0: float, thG0: float, grid: np.ndarray,
               cheap_G: np.ndarray) -> np.ndarray:
    """theta_K at ``t`` under a medium or a brake: (|J* w|, theta_G) integrated on a table over both."""
    g_hi = 1.02 * max(g0, float(np.max(cheap_G)))
    g_lo = max(0.98 * min(g0, float(np.min(cheap_G))), 1e-3 * g_hi)
    gs = np.linspace(g_lo, g_hi, TABLE_G)
    G, T = np.meshgrid(gs, grid, indexing="ij")
    thK, dg, dth = (x.reshape(G.shape) for x in rates(sc, G, T))
    sg, st, sk = (RectBivariateSpline(gs, grid, x) for x in (dg, dth, thK))

    def rhs(_s, y):
        return [float(sg(y[0], y[1])[0, 0]), float(st(y[0], y[1])[0, 0])]

    def stopped(_s, y):
        return y[0] - g_lo

    stopped.terminal = True
    try:
        sol = solve_ivp(guarded(rhs, MAX_CALLS, "the predicted slow motion"), (t0, float(t[-1])), [g0, thG0],
                        rtol=1e-10, atol=1e-12, method="DOP853", dense_output=True, events=stopped)
    except RightSideError:
        return np.full(t.shape, np.nan)
    if sol.status < 0 or sol.sol is None:
        return np.full(t.shape, np.nan)
    reached = min(float(sol.t[-1]), float(t[-1]))
    y = sol.sol(np.minimum(t, reached))
    return sk(y[0], y[1], grid=False)
