"""How far the spherical pendulum's averaged model (docs/models.md B.6) strays from the full model: a bound on
max |theta_averaged - theta_full| over [0, t_end] (rad), and the pendulum's own swing amplitude (issue 15).

The averaged model neglects two kinds of terms; the estimate measures each one's effect on theta over the run's
own horizon [0, t_end] (so the horizon against the e-folding time needs no separate factor):

- linear terms: the detuning |lambda_1 - Omega|/Omega, the coupling g/|Omega|, the damping ct/lambda_1 beyond
  first order, and the non-resonant pendulum mode 2. The exact linear theory (docs/models.md B.3,
  ``linear.state_matrix``)
  keeps them all, so ``linear_gap`` = max |theta_averaged - theta_linear| is their whole effect at first order
  in the amplitudes. Where the full model is nearly linear the actual error equals it (to ~1 %).
- nonlinear terms (both models are linear in the amplitudes): first an amplitude-dependent detuning. The spin rate
  omega_z = |H| cos(theta)/C rises by ~W theta0^2/2 as the nutation decays, which moves sigma = lambda_1 - Omega
  by C/A times that, and the pendulum's own frequency shifts by ~AMPLITUDE_SHIFT omega_0 a^2 with its swing a,
  taken from linear theory (in weakly coupled cases a is ~6 theta0 or more, so a, not theta0, sets the
  nonlinearity). ``detuning_gap`` = how far the averaged theta moves when sigma is shifted by up to that much
  either way: at both ends, and at the resonance (sigma = 0) where the detuning can reach it (issue 23: a
  detuned pendulum pulled into resonance decays faster than either end says; read at the ends only, the estimate
  missed by up to 2.4x there). The swing that decides the reach is the larger of linear theory's and the one
  the bob has at exact resonance: a bob pulled towards the resonance swings wider as it nears it, so it can
  jump there from a swing linear theory keeps too small (issue 23's fresh check: 1.22x under, with the linear
  swing's detuning a third of the way); the reach takes the pivot's measured frequency rise SWING_SHIFT omega_0
  a^2, not AMPLITUDE_SHIFT's scale. At exact resonance a detuning is second order in the shift, while the
  full model's decay rate still moves at first order (by ~0.26 shift/g on set R at eps = 1/8, 0.5 deg: the energy
  moving between carrier and bob modulates the detuning as it goes), so ``rate_gap`` = how far theta moves when
  the averaged decay runs RATE_SHARE shift/g faster or slower.

- the asymmetric carrier's own nonlinearity (issue 23): ``polhode_gap``, how far the frozen carrier's exact free
  nutation swings beyond its linearisation; 0 when A = B.

bracket = SAFETY_LINEAR * (linear_gap + polhode_gap) + SAFETY * max(detuning_gap, rate_gap). The linear part is
exact theory: where the nonlinear parts are negligible the actual error is linear_gap to 1 %, and SAFETY_LINEAR is
small.
AMPLITUDE_SHIFT and RATE_SHARE are scales, not fits; SAFETY covers what they miss: measured over the calibration
study (python -m bench fidelity --system spherical_pendulum on seeds 101, 202, 303 and 15, and the pendulum rows of
seed 2027; docs/models.md B.10 quotes the runs).

The bracket says how far the averaged theta could move, not where the full model goes, so it sits 2-9x above the
actual error. A prediction does better (issue 23): ``predicted_gap``, the averaged model's largest distance from
the full equations averaged numerically (physics/systems/pendulum/normal_form.py), which every nonlinear effect
enters as the full model has it. Over the 1330 averaged rows of the fidelity studies in bench/results/ before seed
12041, the 803 with a prediction and one steady swing had actual errors 0.42-1.18 times predicted_gap (median 1.00,
1-99 % 0.93-1.08; python -m bench pendulum-prediction, its normal_form summary); SAFETY_PREDICTED leaves 1.1x beyond
the worst. A bob with three steady
swings at the start (``steady_branches``) may jump to its upper branch, which the prediction started at rest does
not follow, so there the bracket alone stands. estimate = min(bracket, SAFETY_PREDICTED predicted_gap +
PREDICTED_FLOOR): each held on every row, so the smaller does.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from scipy.integrate import solve_ivp

from physics.core.guarded import RightSideError, guarded
from physics.scenario.initial import initial_G
from physics.systems.pendulum import normal_form
from physics.systems.pendulum.averaged import AveragedCoefficients, averaged_theta
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.pendulum.linear import SphericalLinear, spherical_linear, state_matrix, transverse_momentum_matrix
from physics.systems.pendulum.models import pack

# Over the pendulum rows of seeds 101, 202, 303, 15 and 2027 with an estimate (419 scenarios), a safety factor on
# each part of the estimate. Linear: where max(detuning_gap, rate_gap) < linear_gap / 100 (16 rows), actual /
# linear_gap was 0.991-1.009, and SAFETY_LINEAR leaves 1.1x beyond it. Nonlinear: with SAFETY_LINEAR on the linear
# part, the worst actual / (SAFETY_LINEAR linear_gap + max(...)) was 1.51 (seed 2027, a resonant bob), and SAFETY
# leaves 1.32x beyond it. One factor of 1.8 on both before made the estimate 1.8x the actual error wherever the
# pendulum is all but linear, however exact linear theory is there.
SAFETY_LINEAR = 1.1
SAFETY = 2.0
SAFETY_PREDICTED = 1.3  # the worst actual / predicted_gap was 1.18 (module docstring): 1.1x beyond it, as SAFETY_LINEAR
PREDICTED_FLOOR = 1e-6  # rad: below it the full model's own tolerance and the fit's rounding may decide
AMPLITUDE_SHIFT = 0.25  # the pendulum's frequency shift per swing^2, in units of omega_0 (a pendulum's ~a^2/8..a^2/4)
# The bob's mode-1 frequency rise per swing^2 (units of omega_0) on each pivot, measured on a massive carrier
# (tests/test_pendulum_accuracy.py: 0.372-0.375 and 0.248-0.252 for swings 0.1-0.3 rad, omega_0/W 1.2-5). Whether
# the swing can carry the detuning to the resonance is a yes or no that no safety factor repairs, so the reach
# uses these, not AMPLITUDE_SHIFT's scale: with a^2/4 on a Cardan pivot it judged a bob 1.2x short of the
# resonance that the full model reached (seed 4099 scenario 26 made symmetric: 9.9e-3 rad against 9.7e-3 stated)
SWING_SHIFT = {"cardan": 0.375, "isotropic": 0.25}
RATE_SHARE = 0.3  # the decay rate's relative change per shift/g: 0.26 measured at resonance (set R, eps 1/8)
SWING_MAX = 1.0  # rad, the bob's largest swing in linear theory the conditions allow: the study's range (validity.py)
POINTS_PER_TURN = 8  # grid points per period of the fastest linear frequency, to see the ripple's peaks
MIN_POINTS, MAX_POINTS = 2001, 40001  # the grid's size: the slow envelope always, the ripple while affordable
POLHODE_TURNS = 4  # free-nutation turns over which polhode_gap reads theta's extremes (they come in each turn)
POLHODE_MAX_TURNS = 100  # the most turns of its fastest rate the exact free motion may take over them (the study's ~10)
POLHODE_MAX_CALLS = 1_000_000  # right sides for those turns (DOP853 at rtol 1e-11 takes some hundreds a turn)


@dataclass(frozen=True)
class Parts:
    """The estimate's parts (module docstring): linear_gap, detuning_gap, rate_gap (rad), the bob's largest
    swing a in linear theory (rad), the nonlinear detuning shift (rad/s), the coupling rate g = sqrt|kappa1
    kappa2| (1/s) and the resonance's width max(g, |s_1 - s_2|) (1/s; the damping or the detuning where they
    split the averaged exponents more than the coupling does)."""

    linear_gap: float
    detuning_gap: float
    rate_gap: float
    a: float
    shift: float
    g: float
    width: float
    polhode_gap: float = 0.0
    resonance_gap: float = 0.0  # the part of detuning_gap read at sigma = 0 (0 where the swing cannot reach it)
    predicted_gap: float = math.inf  # max |theta_averaged - the normal form's theta| (inf: no prediction)
    branches: int = 1  # the bob's steady swings at the start: 3 where it may jump to an upper branch

    @property
    def bracket(self) -> float:
        """SAFETY_LINEAR (linear_gap + polhode_gap) + SAFETY max(detuning_gap, rate_gap); inf where a growing
        mode overflowed."""
        b = SAFETY_LINEAR * (self.linear_gap + self.polhode_gap) + SAFETY * max(self.detuning_gap, self.rate_gap)
        return b if math.isfinite(b) else math.inf

    @property
    def predicted(self) -> float:
        """SAFETY_PREDICTED predicted_gap + PREDICTED_FLOOR where the bob has one steady swing; inf otherwise (a bob
        that may jump to its upper branch, or no prediction)."""
        if self.branches != 1 or not math.isfinite(self.predicted_gap):
            return math.inf
        return SAFETY_PREDICTED * self.predicted_gap + PREDICTED_FLOOR

    @property
    def bound(self) -> float:
        """The smaller of the bracket and the prediction: each holds on its own (module docstring)."""
        return min(self.bracket, self.predicted)


@lru_cache(maxsize=128)  # auto's choice, derived and the conditions all ask for the same scenario's parts
def parts(p: SphericalLinear, wx: float, wy: float, t_end: float, swing_shift: float) -> Parts:
    """The estimate's parts for linear parameters p, the carrier started at transverse rate (wx, wy) with the
    bob at rest, over [0, t_end] (s); swing_shift is the pivot's SWING_SHIFT."""
    from physics.systems.pendulum.propagate import propagate

    t = _grid(p, t_end)
    Y = propagate(state_matrix(p), np.array([wx, wy, 0.0, 0.0, 0.0, 0.0]), t)
    H = Y @ transverse_momentum_matrix(p).T
    theta_lin = np.arctan2(np.hypot(H[:, 0], H[:, 1]), p.C * p.W)
    a = float(np.max(np.hypot(Y[:, 2], Y[:, 3])))
    co = AveragedCoefficients(p)
    u0 = np.array([wx + 1j * wy, 0.0 + 0j])
    theta_avg, _ = averaged_theta(co, u0, p.W, t)
    theta0 = float(theta_lin[0])
    spin_up = (p.C / co.A) * p.W * theta0**2 / 2
    shift = spin_up + AMPLITUDE_SHIFT * p.omega0 * a**2
    g = math.sqrt(abs(co.kappa1 * co.kappa2))
    # the bob's swing at exact resonance, where the exchange with the carrier is fastest: a bob whose swing pulls it
    # towards the resonance swings wider the closer it gets, and may jump there (a hardening oscillator's jump);
    # its detuning at that swing says whether it can (capped at the 1 rad the conditions allow)
    resonant = copy.copy(co)
    resonant.sigma = 0.0
    th_resonant, U_resonant = averaged_theta(resonant, u0, p.W, t)
    a_jump = min(float(np.max(np.abs(U_resonant[:, 1]))), SWING_MAX)
    reach = spin_up + swing_shift * p.omega0 * max(a, a_jump) ** 2
    # the detuning anywhere in sigma +- shift: the averaged theta moves most at either end or, where the swing can
    # carry sigma to the resonance (|sigma| < reach), at sigma = 0
    resonance_gap = float(np.max(np.abs(th_resonant - theta_avg))) if abs(co.sigma) < reach else 0.0
    detuning_gap = resonance_gap
    for sigma in (co.sigma + shift, co.sigma - shift):
        shifted = copy.copy(co)
        shifted.sigma = sigma
        th, _ = averaged_theta(shifted, u0, p.W, t)
        detuning_gap = max(detuning_gap, float(np.max(np.abs(th - theta_avg))))
    s1, s2 = co.exponents()
    width = max(g, abs(s1 - s2))
    eps = min(RATE_SHARE * shift / width, 1.0) if width > 0 else 1.0
    rate_gap = 0.0
    for sign in (1.0, -1.0):
        th, _ = averaged_theta(co, u0, p.W, t * (1 + sign * eps))
        rate_gap = max(rate_gap, float(np.max(np.abs(th - theta_avg))))
    return Parts(linear_gap=float(np.max(np.abs(theta_avg - theta_lin))), detuning_gap=detuning_gap,
                 rate_gap=rate_gap, a=a, shift=shift, g=g, width=width, polhode_gap=polhode_gap(p, wx, wy, t_end),
                 resonance_gap=resonance_gap)


def polhode_gap(p: SphericalLinear, wx: float, wy: float, t_end: float) -> float:
    """How far the frozen carrier's exact free nutation reaches beyond its linearisation (rad): the larger
    difference of the highest and of the lowest theta over POLHODE_TURNS turns (or t_end), 0 on a symmetric carrier,
    whose free nutation keeps theta constant in both.

    On an asymmetric carrier theta swings twice a turn, and the linear gap (the averaged model has no swing) is
    mostly that swing, exact to first order in theta only: on a fresh draw with theta0 = 0.27 rad the actual error
    was 1.11 times linear_gap, while the nonlinear gaps were 1 % of it, and this gap, 4.1e-3 rad, is the 4.0e-3 by
    which the actual error exceeded linear_gap. The extremes, not the difference at each time: the exact polhode
    turns at its own amplitude-dependent rate, and the averaged model's error responds to the swing's reach."""
    if p.B is None or p.B == p.A:
        return 0.0

    bob = p.mu * p.D**2  # the frozen system: the bob at rest on the axis adds mu D^2 to A and B
    A, B, C, W = p.A + bob, p.B + bob, p.C, p.W
    size = math.sqrt(wx * wx + wy * wy + W * W)
    if size == 0:
        return 0.0
    rate = abs(W) * math.sqrt(abs((C - A) * (C - B) / (A * B)))
    if not rate > 0:  # a spin at 90 deg, or C = A or B: no linear nutation to compare with
        return math.inf
    span = min(t_end, POLHODE_TURNS * 2 * math.pi / rate)
    # the exact motion turns at up to ~|w| max|Euler coefficient|; where that is many times the linear rate (a
    # nutation near 90 deg, a spin near the separatrix) the linearisation does not hold, and integrating would cost
    # without bound: no estimate
    fastest = size * max(abs(B - C) / A, abs(C - A) / B, abs(A - B) / C)
    if not span * fastest <= POLHODE_MAX_TURNS * 2 * math.pi:
        return math.inf
    t = np.linspace(0.0, span, 4001)

    def euler(_, w):
        return [(B - C) / A * w[1] * w[2], (C - A) / B * w[2] * w[0], (A - B) / C * w[0] * w[1]]

    try:  # guarded: products of huge rates overflow, and solve_ivp loops for good on a right side that is not finite
        sol = solve_ivp(guarded(euler, POLHODE_MAX_CALLS, "the frozen carrier's free nutation"), (0.0, span),
                        [wx, wy, W], method="DOP853", rtol=1e-11, atol=1e-14 * size, t_eval=t)
    except RightSideError:
        return math.inf
    if not sol.success:
        return math.inf
    w = sol.y
    exact = np.arctan2(np.hypot(A * w[0], B * w[1]), C * w[2])
    c, s = np.cos(rate * t), np.sin(rate * t)  # linearised about w3 = W: A w1' = (B - C) W w2, B w2' = (C - A) W w1
    w1 = wx * c + (B - C) / A * W * wy / rate * s
    w2 = wy * c + (C - A) / B * W * wx / rate * s
    linear = np.arctan2(np.hypot(A * w1, B * w2), C * W)
    return float(max(abs(exact.max() - linear.max()), abs(exact.min() - linear.min())))


def scenario_parts(sc, predict: bool = True) -> Parts:
    """``parts`` of a spherical-pendulum scenario. A mode that grows (a damper that destabilises the nutation) or
    extreme input overflows: then every part is inf, which fails the conditions and leaves no estimate. With
    ``predict=False`` the normal form is not run (``predicted_gap`` stays inf): the conditions read the swing and the
    detuning only, and a scenario that fails them needs no prediction."""
    p = spherical_linear(pendulum_system(sc))
    w0, _, _ = initial_G(sc)
    try:
        with np.errstate(all="ignore"):
            q = parts(p, float(w0[0]), float(w0[1]), float(sc.run.t_end), SWING_SHIFT[sc.pendulum.pivot])
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        q = None
    if q is None or not all(map(math.isfinite, (q.linear_gap, q.detuning_gap, q.rate_gap, q.a, q.shift))):
        return Parts(*(math.inf,) * 5, g=0.0, width=0.0, polhode_gap=math.inf, resonance_gap=math.inf)
    if not predict:
        return q
    w = (float(w0[0]), float(w0[1]), float(w0[2]))
    try:
        with np.errstate(all="ignore"):
            branches = steady_branches(p, w, SWING_SHIFT[sc.pendulum.pivot])
            gap = _predicted_gap(p, tuple(pack(sc)), w, float(sc.run.t_end)) if branches == 1 else math.inf
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        branches, gap = 1, math.inf
    return replace(q, predicted_gap=gap, branches=branches)


def steady_branches(p: SphericalLinear, w0, swing_shift: float) -> int:
    """How many steady swings the bob has at the start, forced by the initial nutation: the roots x = a^2 > 0 of
    x ((sigma + swing_shift omega_0 x)^2 + gamma1^2) = |kappa2 Phihat_0|^2, one or three. With three the hardening
    bends the resonance over the forcing, and the bob may settle on its upper branch, which no averaged equation
    started at rest follows (docs/models.md B.10)."""
    co = AveragedCoefficients(p)
    h = swing_shift * p.omega0
    drive = abs(co.kappa2 * complex(w0[0], w0[1]))
    roots = np.roots([h * h, 2 * co.sigma * h, co.sigma**2 + co.gamma1**2, -drive * drive])
    real = roots[np.abs(roots.imag) <= 1e-9 * np.maximum(1.0, np.abs(roots))].real
    return int(np.sum(real > 0))


def _grid(p: SphericalLinear, t_end: float) -> np.ndarray:
    """The estimate's time grid: the slow envelope always, the fastest linear ripple while affordable."""
    fastest = float(np.max(np.abs(np.linalg.eigvals(state_matrix(p)).imag)))
    n = int(np.clip(t_end * fastest / (2 * math.pi) * POINTS_PER_TURN, MIN_POINTS, MAX_POINTS))
    return np.linspace(0.0, t_end, n)


@lru_cache(maxsize=128)
def _predicted_gap(p: SphericalLinear, packed: tuple, w0: tuple, t_end: float) -> float:
    """max |theta_averaged - theta predicted by the normal form| over the estimate's grid (rad); inf where the
    normal form does not apply."""
    t = _grid(p, t_end)
    prediction = normal_form.predict(np.array(packed), w0, t)
    if prediction is None:
        return math.inf
    theta_avg, _ = averaged_theta(AveragedCoefficients(p), np.array([w0[0] + 1j * w0[1], 0.0 + 0j]), p.W, t)
    gap = float(np.max(np.abs(prediction.theta - theta_avg)))
    return gap if math.isfinite(gap) else math.inf


def pendulum_amplitude(sc) -> float:
    """The pendulum's largest swing |alpha + i beta| (rad) over [0, t_end] in linear theory, started at rest."""
    return scenario_parts(sc, predict=False).a


def averaged_error_bound(sc) -> float:
    """A bound on max |theta_averaged - theta_full| over [0, t_end], rad (module docstring)."""
    return scenario_parts(sc).bound
