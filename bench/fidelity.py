"""``python -m bench fidelity``: the cheaper fidelities' actual theta error against their stated estimate (issue 15).

A seeded random set of valid scenarios over the domain the issue lists (moving mass: oblate and prolate,
near-spherical C/A in 0.85..1.15, a few triaxial bodies, m rho^2/A up to 0.7, theta0 up to 1.2 rad, weak and
strong damping, with and without cavity, medium and braking; spherical pendulum: resonant and detuned, weak and
strong damping). Each runs the full model (the reference) and every cheaper fidelity of its system; the actual
error is max |theta - theta_full| over the common time span, the estimate is what ``physics.derived`` states
today (``<fidelity>_error_bound``, else ``auto_error_bound`` when auto picks that fidelity, else none).

Writes ``<out>/fidelity[_quick].csv`` (one row per scenario x cheaper fidelity, skipped scenarios included with
their reason), ``<out>/fidelity[_quick].meta.json`` (machine, command, counts) and ``<img>/fidelity[_quick].png``.
The summary gives, per system and fidelity, the over-estimate's spread (percentiles of estimate/actual), the
coverage (the share of the scenarios inside the cheaper models' own conditions with a finite estimate), and for
auto at 1e-2 and 1e-3 rad the share of an oracle's cheaper runs it takes too and its wall time against the
oracle's. ``--rescore CSV`` scores a study's rows again with today's estimates without running any model.
"""

from __future__ import annotations

import csv
import json
import math
import re
import sys
import textwrap
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from bench.cli import bounded, study_parser

from .machine import machine

ROOT = Path(__file__).resolve().parents[1]

# full-model cost model for the step cap: DOP853 at rtol 1e-10 took ~70 steps per fast period on
# assets/scenarios/oblate_settling.toml (6.6e6 steps over 95 000 periods of Omega); the pendulum ~40 per period
STEPS_PER_PERIOD = {"moving_mass": 70.0, "spherical_pendulum": 40.0, "wheel": 40.0}
MAX_STEPS = {True: 5e6, False: 2e7}  # quick / full study: the full model's estimated steps per scenario
SAMPLES = 1001
RTOL = 1e-10

# the domain (the list); the tests check generated scenarios against these
C_OVER_A = (0.4, 1.6)  # whole range; near-spherical draws come from NEAR_SPHERE
NEAR_SPHERE = (0.85, 1.15)
MIN_ASPHERICITY = 0.04  # |1 - C/A| below this the slow motion is too slow to see within any step cap
KAPPA = (0.01, 0.7)  # m rho^2 / A
ETA = (0.01, 0.25)  # m / M: with KAPPA, m rho^2 / (1 - m/M) < A as the carrier check requires
CHI_WEAK, CHI_STRONG = (0.2, 0.5), (1.0, 3.0)  # chi / Omega
THETA0_MASS = (0.02, 1.5)
REST_SHARE = 0.2  # moving-mass draws whose mass starts at rest (a free oscillation) instead of quasi-static
EPS = (0.04, 0.2)  # |w0| / Omega
THETA0_PENDULUM = (0.02, 0.35)
PENDULUM_C_OVER_A = (1.05, 1.8)
N_SLOW = (0.5, 3.0)  # horizon in slow times (moving mass) or linear e-folding times (pendulum)

COLUMNS = ["index", "system", "kind", "status", "note", "eps", "C_over_A", "B_over_A", "kappa", "eta", "theta0",
           "mass_state", "damping", "cavity", "medium", "braking", "detuning", "n_slow", "t_end", "fidelity",
           "actual_error", "estimate", "estimate_key", "ratio", "auto_fidelity", "auto_0.01", "auto_0.001",
           "choose_s_0.01", "choose_s_0.001", "wall_full_s", "wall_s", "steps_full_est", "J", "c", "axis3", "inside",
           "scenario"]


# ---- the scenario generator (no simulation) ---------------------------------------------------------------

def _uniform(rng, lo_hi) -> float:
    return float(rng.uniform(*lo_hi))


def _loguniform(rng, lo_hi) -> float:
    return float(math.exp(rng.uniform(math.log(lo_hi[0]), math.log(lo_hi[1]))))


def _shape(rng) -> float:
    """C/A: 40 % near-spherical (0.85..1.15), else oblate or prolate over the whole range; never within
    MIN_ASPHERICITY of a sphere."""
    while True:
        lo_hi = NEAR_SPHERE if rng.random() < 0.4 else C_OVER_A
        r = _uniform(rng, lo_hi)
        if abs(1.0 - r) >= MIN_ASPHERICITY:
            return r


def _mass_slow_rate(d: dict, sc) -> float:
    """1/s: the moving mass's slow rate, |D| G0^4 / (A C^4) (Gamma2 lambda, seed 004 (24)) plus the cavity's
    H G0^2 / (A^2 C) plus the medium's lambda: the scale on which theta moves."""
    A, C, G0 = sc.body.A, sc.body.C, float(d["G0"])
    rate = abs(float(d["D"])) * G0**4 / (A * C**4) + abs(float(d["H"])) * G0**2 / (A * A * C)
    return rate + (sc.medium.lambda_ if sc.medium is not None else 0.0)


def mass_case(rng) -> tuple[dict, dict]:
    """(scenario dict, descriptors) of one moving-mass draw."""
    import physics

    ca = _shape(rng)
    triaxial = rng.random() < 0.15  # only the full model allows A != B; the cheaper ones record the refusal
    ba = 1.0 + _uniform(rng, (0.01, 0.1)) if triaxial else 1.0
    kappa = _uniform(rng, KAPPA)
    eta = _uniform(rng, ETA)
    rho = _uniform(rng, (0.5, 2.0))
    theta0 = _uniform(rng, THETA0_MASS)
    eps = _loguniform(rng, EPS)
    strong = rng.random() < 0.5
    body = {"A": 1.0, "C": ca, "M": kappa / rho**2 / eta}
    if triaxial:
        body["B"] = ba
    data = {"body": body, "mass": {"m": kappa / rho**2, "rho": rho, "Omega": 1.0},
            "initial": {"G0": 1.0, "theta0": theta0, "mass_state": "quasistatic"},
            "run": {"t_end": 1.0, "samples": SAMPLES, "rtol": RTOL}}
    # Omega from eps: |w0| hardly depends on Omega (the quasistatic mass shifts it by O(eps^2))
    omega0 = physics.coefficients(physics.Scenario.from_dict(data)).omega0
    Omega = omega0 / eps
    # weak: chi |w0| / Omega^2 well inside the averaged condition; strong: chi ~ Omega (may leave it). The slow
    # rate grows with chi up to ~Omega: weaker damping than CHI_WEAK is beyond any step cap
    chi = Omega * _uniform(rng, CHI_STRONG if strong else CHI_WEAK)
    data["mass"].update(Omega=Omega, chi=chi)
    if rng.random() < REST_SHARE:
        data["initial"]["mass_state"] = "rest"
    cavity = rng.random() < 0.3
    if cavity:
        data["cavity"] = {"beta": _loguniform(rng, (50.0, 2000.0)), "nu": 20.0, "a0": 0.1}
    sc = physics.Scenario.from_dict(data)
    rate0 = _mass_slow_rate(physics.derived(sc), sc)
    medium = rng.random() < 0.3
    braking = medium and rng.random() < 0.5
    if medium:
        data["medium"] = {"lambda": rate0 * _uniform(rng, (0.2, 2.0))}
    if braking:
        data["control"] = {"b": data["medium"]["lambda"] * _uniform(rng, (0.5, 3.0)), "law": "K"}
    sc = physics.Scenario.from_dict(data)
    d = physics.derived(sc)
    n_slow = _uniform(rng, N_SLOW)
    slow_time = 1.0 / _mass_slow_rate(d, sc)
    data["run"]["t_end"] = float(n_slow * slow_time)
    desc = dict(system="moving_mass", kind=("oblate" if ca > 1 else "prolate") + (" triaxial" if triaxial else ""),
                C_over_A=ca, B_over_A=ba, kappa=kappa, eta=eta, theta0=theta0, damping="strong" if strong else "weak",
                cavity=cavity, medium=medium, braking=braking, detuning="", n_slow=n_slow, slow_time=slow_time,
                mass_state=data["initial"]["mass_state"])
    return data, desc


# quadratic friction's draw (``--system quadratic_friction``, its own set, seed 000 section 2): the mass alone
# (the closed form (2.11) covers it only so), a symmetric body, a quasi-static start. lam_q is drawn through
# chi_eq, the viscous damping with the same slow rate at theta0 (accuracy.equivalent_chi), over the viscous
# study's chi / Omega and below it (the friction weakens as the nutation decays, so every run ends weak)
QUADRATIC_CHI = (0.05, 3.0)  # chi_eq(theta0) / Omega, log-uniform


def quadratic_case(rng) -> tuple[dict, dict]:
    """(scenario dict, descriptors) of one quadratic-friction draw."""
    import physics
    from physics.systems.moving_mass.accuracy import equivalent_chi

    ca = _shape(rng)
    kappa, eta = _uniform(rng, KAPPA), _uniform(rng, ETA)
    rho = _uniform(rng, (0.5, 2.0))
    theta0 = _uniform(rng, THETA0_MASS)
    eps = _loguniform(rng, EPS)
    data = {"body": {"A": 1.0, "C": ca, "M": kappa / rho**2 / eta},
            "mass": {"m": kappa / rho**2, "rho": rho, "Omega": 1.0, "chi": 0.0, "lam_q": 1.0},
            "initial": {"G0": 1.0, "theta0": theta0, "mass_state": "quasistatic"},
            "run": {"t_end": 1.0, "samples": SAMPLES, "rtol": RTOL}}
    omega0 = physics.coefficients(physics.Scenario.from_dict(data)).omega0
    data["mass"]["Omega"] = Omega = omega0 / eps
    chi_eq = _loguniform(rng, QUADRATIC_CHI)  # / Omega; chi_eq is proportional to lam_q, 1 here
    data["mass"]["lam_q"] = Omega * chi_eq / equivalent_chi(physics.Scenario.from_dict(data))
    sc = physics.Scenario.from_dict(data)
    co = physics.coefficients(sc)
    # theta' = gamma sin|sin| cos^5 (seed 000 (2.9)): the slow time is theta0 over the starting rate, capped where
    # cos^5 all but stops a prolate body near pi/2
    rate0 = abs(co.gamma) * math.sin(theta0) ** 2 * max(math.cos(theta0) ** 5, 1e-3)
    slow_time = theta0 / rate0
    n_slow = _uniform(rng, N_SLOW)
    data["run"]["t_end"] = float(n_slow * slow_time)
    desc = dict(system="moving_mass", kind="quadratic " + ("oblate" if ca > 1 else "prolate"), C_over_A=ca,
                B_over_A=1.0, kappa=kappa, eta=eta, theta0=theta0, damping=f"chi_eq/Omega {chi_eq:.3g}",
                cavity=False, medium=False, braking=False, detuning="", n_slow=n_slow, slow_time=slow_time,
                mass_state="quasistatic")
    return data, desc


# the spherical pendulum's draw: every scenario must run in both models (issue 15). The bob's rest height |h + l|
# above O sets the coupling: near 0 it vanishes and the e-folding time runs to months of simulated time
PENDULUM_REACH = (0.03, 0.8)  # m, |h + l|, log-uniform: weak coupling (where the averaged model is good) to strong
PENDULUM_DAMPING = {"weak": (0.02, 0.5), "strong": (1.0, 8.0)}  # ct / Omega: pivot damping rate over nutation
PENDULUM_STEPS = 1e6  # the full model's estimated steps (STEPS_PER_PERIOD): longer horizons are shortened to this
PENDULUM_SWING_MAX = 1.0  # rad: the bob's linear-theory swing; beyond, theta0 shrinks (a Cardan pivot stops at 90 deg)


def pendulum_case(rng) -> tuple[dict, dict]:
    """(scenario dict, descriptors) of one spherical-pendulum draw: a carrier near the issue's reproduction,
    resonant or detuned, weakly or strongly damped (ct/Omega), a few slightly triaxial. The damping is drawn
    relative to the nutation (an absolute c_d of 1..8 on a light short bob made the full model too stiff for
    DOP853), the horizon is capped at PENDULUM_STEPS full-model steps (which also keeps the averaged model's
    attitude within its budget), and where the bob would swing past PENDULUM_SWING_MAX theta0 is scaled down
    (redrawn if that takes it below THETA0_PENDULUM)."""
    import physics
    from physics.systems.pendulum.accuracy import pendulum_amplitude
    from physics.systems.pendulum.averaged import MAX_SUBSTEPS, QUAT_STEP

    while True:
        A = 100.0
        # oblate carriers only: a prolate carrier's nutation turns against the spin, so "resonant" cannot be tuned
        ca = _uniform(rng, PENDULUM_C_OVER_A)
        triaxial = rng.random() < 0.15
        ba = 1.0 + _uniform(rng, (0.01, 0.1)) if triaxial else 1.0
        theta0 = _loguniform(rng, THETA0_PENDULUM)  # log: the bob swings ~6-20 theta0, small ones matter
        W = _uniform(rng, (0.5, 2.0))
        strong = rng.random() < 0.5
        resonant = rng.random() < 0.5
        body = {"A": A, "C": ca * A, "M": _uniform(rng, (300.0, 800.0))}
        if triaxial:
            body["B"] = ba * A
        m, l = _loguniform(rng, (0.3, 5.0)), _uniform(rng, (0.2, 1.0))
        reach = _loguniform(rng, PENDULUM_REACH) * (1.0 if rng.random() < 0.5 else -1.0)
        zeta = _loguniform(rng, PENDULUM_DAMPING["strong" if strong else "weak"])
        pend = {"m": m, "l": l, "h": reach - l, "k": "resonant", "c_d": zeta * (ca - 1.0) * W * m * l * l}
        data = {"body": body, "pendulum": pend,
                "initial": {"G0": ca * A * W / math.cos(theta0), "theta0": theta0},
                "run": {"t_end": 1.0, "samples": SAMPLES, "rtol": RTOL}}
        detuning = 1.0
        if not resonant:  # near (0.9..1.1) or far (0.5..2) from resonance, never on it
            k_res = float(physics.derived(physics.Scenario.from_dict(data))["k_resonant"])
            while abs(detuning - 1.0) < 0.02:
                detuning = _uniform(rng, (0.9, 1.1)) if rng.random() < 0.5 else _loguniform(rng, (0.5, 2.0))
            pend["k"] = k_res * detuning
        d = physics.derived(physics.Scenario.from_dict(data))
        n_slow = _uniform(rng, N_SLOW)
        tau = float(d["tau_e_linear"])
        fast = max(abs(float(d["omega_0"])), abs(float(d["lambda_2"])), abs(float(d["Omega"])))
        attitude_rate = W * (1 + math.tan(theta0)) + 2 * abs(float(d["Omega"])) + abs(float(d["lambda_1"]))
        cap = min(PENDULUM_STEPS * 2 * math.pi / (STEPS_PER_PERIOD["spherical_pendulum"] * fast),
                  0.5 * MAX_SUBSTEPS * QUAT_STEP / attitude_rate)
        t_end = min(n_slow * tau, cap) if math.isfinite(tau) else cap
        data["run"]["t_end"] = float(t_end)
        swing = pendulum_amplitude(physics.Scenario.from_dict(data))
        if swing > PENDULUM_SWING_MAX:
            # the swing is linear in theta0: scale theta0 down (redrawing the whole case instead would drop most
            # weakly damped resonant ones, whose bob swings the widest), or redraw below THETA0_PENDULUM
            theta0 *= PENDULUM_SWING_MAX / swing * _uniform(rng, (0.3, 0.9))
            if theta0 < THETA0_PENDULUM[0]:
                continue
            data["initial"] = {"G0": ca * A * W / math.cos(theta0), "theta0": theta0}
        desc = dict(system="spherical_pendulum", kind="resonant" if resonant else "detuned", C_over_A=ca,
                    B_over_A=ba, kappa=float(d.get("coupling_muD2_over_A", float("nan"))), theta0=theta0,
                    damping="strong" if strong else "weak", cavity=False, medium=False, braking=False,
                    detuning=detuning, n_slow=t_end / tau if math.isfinite(tau) else 0.0, slow_time=tau)
        return data, desc


# the wheel damper's draw (``--system wheel``, its own set: the moving-mass and pendulum draws stay as they were).
# Over the closed form's domain and past its edges, where the estimate must say it claims nothing
WHEEL_C_OVER_A = (1.02, 2.0)  # oblate: the spin about e3 is the one the bearing leads to
WHEEL_NEAR_SPHERE = (1.005, 1.05)
WHEEL_PROLATE = (0.6, 0.98)  # an edge: the nutation grows, no claim
WHEEL_J = (0.005, 0.3)  # kg m^2 with A = 1: the slider's range
WHEEL_C = (0.005, 3.0)  # N m s, log-uniform; some draws have c = 0 (a free wheel)
WHEEL_THETA0 = (0.003, 0.15)  # rad, log-uniform: past the closed form's 0.1
WHEEL_EFOLDS = (0.3, 6.0)  # horizon in linear e-folding times of the nutation ...
WHEEL_TURNS = (5.0, 4000.0)  # ... or in nutation periods (weak damping), past the estimate's 3000
WHEEL_STIFF = 2e5  # t_end x the fastest linear rate (the wheel's relaxation): DOP853's steps stay ~5e4


def wheel_case(rng) -> tuple[dict, dict]:
    """(scenario dict, descriptors) of one wheel-damper draw: oblate (some near a sphere) or prolate, symmetric
    or triaxial (B between A and C, some near the separatrix B ~ C), a transverse, axial or random axis, weak to
    strong bearings, theta0 to 0.15 rad, horizons of a few e-folds or up to thousands of turns."""
    import physics
    from physics.systems.wheel import linear

    while True:
        r = rng.random()
        ca = _uniform(rng, WHEEL_PROLATE if r < 0.1 else WHEEL_NEAR_SPHERE if r < 0.2 else WHEEL_C_OVER_A)
        triaxial = rng.random() < 0.5
        ba = 1.0 + _uniform(rng, (0.0, 0.3 if ca < 1 else min(0.3, 0.95 * (ca - 1.0)))) if triaxial else 1.0
        k = rng.random()
        axis = [1.0, 0.0, 0.0] if k < 0.3 else [0.0, 0.0, 1.0] if k < 0.4 else [float(x) for x in rng.normal(size=3)]
        c = 0.0 if rng.random() < 0.08 else _loguniform(rng, WHEEL_C)
        theta0 = _loguniform(rng, WHEEL_THETA0)
        G0 = _uniform(rng, (1.0, 5.0))
        data = {"body": {"A": 1.0, "B": ba, "C": ca, "M": 1.0},
                "wheel": {"J": _loguniform(rng, WHEEL_J), "c": c, "axis": axis},
                "initial": {"G0": G0, "theta0": theta0}, "run": {"t_end": 1.0, "samples": SAMPLES, "rtol": RTOL}}
        sc = physics.Scenario.from_dict(data)
        physics.get_system("wheel").check(sc)
        mode = linear.nutation_mode(sc)
        if mode is None:
            continue
        s = linear.exponents(sc)
        by_efolds = mode.real < 0 and rng.random() < 0.7
        t_end = (_uniform(rng, WHEEL_EFOLDS) / -mode.real if by_efolds
                 else _loguniform(rng, WHEEL_TURNS) * 2 * math.pi / mode.imag)
        # the full model's stiffness and the closed form's attitude budget (5e4 rad of turning)
        t_end = min(t_end, WHEEL_STIFF / float(np.max(np.abs(s))), 5e4 / (G0 / min(1.0, ca)))
        data["run"]["t_end"] = float(t_end)
        desc = dict(system="wheel", kind=("oblate" if ca > 1 else "prolate") + (" triaxial" if triaxial else ""),
                    C_over_A=ca, B_over_A=ba, J=data["wheel"]["J"], c=c, theta0=theta0,
                    damping="none" if c == 0 else ("efolds" if by_efolds else "turns"), cavity=False,
                    medium=False, braking=False, axis3=float(axis[2] / np.linalg.norm(axis)),
                    n_slow=t_end * -mode.real, slow_time=1 / -mode.real if mode.real < 0 else math.inf)
        return data, desc


# the sets drawn on their own (``--system``): their draw and their files' stem; the other systems' scenarios are
# the whole study's draws, filtered
OWN_SETS = {"wheel": (wheel_case, "fidelity_wheel"), "quadratic_friction": (quadratic_case, "fidelity_quadratic")}


def draw(seed: int, n: int, system: str | None = None) -> list[tuple[dict, dict]]:
    """n (scenario dict, descriptors) pairs, deterministic for the seed: two thirds moving mass, one third
    pendulum. A draw the scenario code refuses is redrawn (counted in the descriptors as ``redraws``)."""
    import physics

    rng = np.random.default_rng(seed)
    out = []
    redraws = 0
    while len(out) < n:
        make = OWN_SETS[system][0] if system in OWN_SETS else mass_case if len(out) % 3 != 2 else pendulum_case
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                data, desc = make(rng)
                sc = physics.Scenario.from_dict(data)
                check_run = physics.get_system(sc.system).check_run
                if check_run is not None:  # what a run checks beyond reading (the carrier's moments)
                    check_run(sc)
        except physics.ScenarioError:
            redraws += 1
            continue
        desc["redraws"] = redraws
        out.append((data, desc))
    return out


# ---- errors ------------------------------------------------------------------------------------------------

def max_theta_error(t_ref, theta_ref, t, theta) -> tuple[float, float]:
    """(max |theta - theta_ref|, end of the compared span): theta interpolated onto the reference's times over
    the span both cover (a braked run may stop early)."""
    t_ref, theta_ref, t, theta = map(np.asarray, (t_ref, theta_ref, t, theta))
    end = min(float(t_ref[-1]), float(t[-1]))
    keep = t_ref <= end
    diff = np.interp(t_ref[keep], t, theta) - theta_ref[keep]
    return float(np.max(np.abs(diff))), end


def full_steps_estimate(sc, desc: dict) -> float:
    """The full model's DOP853 steps, from the fastest frequency and STEPS_PER_PERIOD."""
    import physics

    d = physics.derived(sc)
    if desc["system"] == "moving_mass":
        fast = max(sc.mass.Omega, float(d.get("eps", 0.0)) * sc.mass.Omega)
    elif desc["system"] == "wheel":
        from physics.systems.wheel import linear

        fast = max(abs(float(d["n"])), float(np.max(np.abs(linear.exponents(sc)))) / 10.0)
    else:
        fast = max(abs(float(d["omega_0"])), abs(float(d["lambda_2"])), abs(float(d["Omega"])))
    return STEPS_PER_PERIOD[desc["system"]] * sc.run.t_end * fast / (2 * math.pi)


def inside_conditions(sc) -> bool:
    """Whether the cheaper models' own conditions hold for ``sc``, those no error estimate is meant to cover: a
    symmetric body (A = B; the spherical pendulum's |A - B|/A up to its ASYM_MAX since issue 23) for every system,
    and for the moving mass its structural conditions (a mass at rest whose wobble dies quickly, Re, lambda/|w0|,
    b/(G0 |w0|); validity.structural_failures). Coverage (``summary``) is the share of these scenarios with a
    finite estimate."""
    from physics.systems.pendulum.validity import ASYM_MAX

    asymmetry = ASYM_MAX if sc.system == "spherical_pendulum" else 1e-9
    if abs(sc.body.A - sc.body.B) > asymmetry * sc.body.A:
        return False
    if sc.system == "moving_mass":
        from physics.systems.moving_mass.validity import structural_failures

        return not structural_failures(sc)
    return True


def _timed(sc, fidelity):
    import physics

    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a model outside its conditions runs anyway: that is the point here
        tr = physics.simulate(sc, fidelity=fidelity)
    return tr, time.perf_counter() - t0


ACCURACIES = (1e-2, 1e-3)  # rad: auto's pick at each (1e-2 is physics' default), against the oracle's


_WARM = False  # whether this process has run every system's estimates once (compiled code loaded)


def _warm() -> None:
    """Choose once for every system's example scenario: the compiled code that estimates use (the pendulum's
    normal form) is loaded or compiled once per process, not charged to the first scenario a worker draws."""
    global _WARM
    import physics

    if _WARM:
        return
    from physics.scenario.initial import initial_G
    from physics.systems.pendulum import normal_form
    from physics.systems.pendulum.models import pack

    for system in physics.SYSTEMS.values():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sc = physics.Scenario.from_toml(system.example)
            physics.choose_fidelity(sc)
            if system.name == "spherical_pendulum":  # the whole normal form, whether or not its fit holds there
                w0, _, _ = initial_G(sc)
                for terms in (True, False):
                    normal_form.predict(pack(sc), w0, np.linspace(0.0, 1.0, 3), terms=terms)
    _WARM = True


def _cold() -> None:
    """Empty the systems' caches (every ``functools.lru_cache`` in physics.systems), so that a choice is timed as
    a new scenario's: with the estimates it computes, not ones another call left behind."""
    for name, module in list(sys.modules.items()):
        if name.startswith("physics.systems") and module is not None:
            for value in list(vars(module).values()):
                if callable(getattr(value, "cache_clear", None)):
                    value.cache_clear()


def auto_picks(sc) -> dict:
    """auto's pick at each of ACCURACIES and the time it takes to choose, error estimates included: each choice is
    timed cold (``_cold``), as a run at that accuracy would pay for them once."""
    import physics

    _warm()
    out = {}
    for acc in ACCURACIES:
        data = sc.to_dict()
        data.setdefault("run", {})["accuracy"] = acc
        asked = physics.Scenario.from_dict(data)
        _cold()
        t0 = time.perf_counter()
        fid, _ = physics.choose_fidelity(asked)
        out[f"auto_{acc:g}"] = fid
        out[f"choose_s_{acc:g}"] = time.perf_counter() - t0
    return out


def _shortened(data: dict, factor: float) -> dict:
    out = json.loads(json.dumps(data))
    out["run"]["t_end"] *= factor
    return out


def run_case(args) -> list[dict]:
    """Rows of one scenario: one per cheaper fidelity, or one ``failed`` row."""
    import physics

    index, data, desc, max_steps = args
    sc = physics.Scenario.from_dict(data)
    steps = full_steps_estimate(sc, desc)
    n_slow, base_note = desc["n_slow"], ""
    if steps > max_steps:
        # shorten the horizon to the cap: the small-eps scenarios, where auto picks a cheaper model, are the
        # long ones, and skipping them would bias the study; a shorter t_end is as valid a scenario
        n_slow *= max_steps / steps
        data = json.loads(json.dumps(data))
        data["run"]["t_end"] = sc.run.t_end * max_steps / steps
        sc = physics.Scenario.from_dict(data)
        base_note = f"horizon shortened to the step cap: {n_slow:.2g} slow times of {desc['n_slow']:.2g} drawn"
        steps = max_steps
    picks = auto_picks(sc)
    d = physics.derived(sc)
    keys = ("system", "kind", "C_over_A", "B_over_A", "kappa", "eta", "theta0", "mass_state", "damping",
            "cavity", "medium", "braking", "detuning", "J", "c", "axis3")
    base = dict(index=index, **{k: desc.get(k, "") for k in keys},
                eps=d.get("eps", ""), t_end=sc.run.t_end, auto_fidelity=d.get("auto_fidelity", ""),
                scenario=json.dumps(data, separators=(",", ":")))
    base.update(steps_full_est=steps, n_slow=n_slow, inside=inside_conditions(sc), **picks)
    try:
        full, wall_full = _timed(sc, "full")
    except physics.ScenarioError as e:
        # the step-count model above can be low (a stiffer mass): shorten to the run's own budget once
        m = re.search(r"would need about ([0-9.e+]+) steps.*budget of ([0-9]+)", str(e))
        if m is None:
            return [dict(base, status="failed", fidelity="full", note=f"full: {e}")]
        return run_case((index, _shortened(data, 0.8 * float(m.group(2)) / float(m.group(1))), desc, max_steps))
    except physics.IntegrationFault as e:
        return [dict(base, status="failed", fidelity="full", note=f"full: {e}")]
    base["wall_full_s"] = wall_full
    rows = []
    for fid in physics.get_system(sc.system).fidelities:
        if fid in ("auto", "full"):
            continue
        key = f"{fid}_error_bound"
        est = float(d[key]) if key in d else None  # inf: the system claims nothing here
        row = dict(base, fidelity=fid, estimate="" if est is None else est, estimate_key=key if est is not None else "")
        try:
            tr, wall = _timed(sc, fid)
        except (physics.ScenarioError, physics.IntegrationFault) as e:
            rows.append(dict(row, status="failed", note=str(e)))
            continue
        err, end = max_theta_error(full.t, full.theta, tr.t, tr.theta)
        span = f"compared over [0, {end:.6g}]" if end < sc.run.t_end * (1 - 1e-9) else ""
        note = "; ".join(x for x in (base_note, span) if x)
        if not math.isfinite(err):  # a model that returned NaN theta: a failure, not an error size
            rows.append(dict(row, status="nan", note=f"{fid} theta not finite", wall_s=wall))
            continue
        ratio = "" if est is None else (err / est if est > 0 else math.inf)
        rows.append(dict(row, status="ok", note=note, actual_error=err, wall_s=wall, ratio=ratio))
    return rows


def oracle(rows: list[dict], acc: float, system: str | None = None) -> dict:
    """auto's total wall time at accuracy ``acc`` (choosing + running its pick) against an oracle's, which knows
    the actual errors and runs the cheapest model that meets ``acc`` (the full model when none does); the share
    of the oracle's cheaper runs auto takes too (``auto_share``). ``system``: only that system's scenarios."""
    by_scen: dict = {}
    for r in rows:
        if r["status"] in ("ok", "nan", "failed") and r.get("wall_full_s", "") != "" \
                and system in (None, r["system"]):
            by_scen.setdefault(r["index"], []).append(r)
    auto_s = oracle_s = 0.0
    auto_cheap = oracle_cheap = held = both = 0
    for group in by_scen.values():
        full_s = float(group[0]["wall_full_s"])
        ok = {r["fidelity"]: r for r in group if r["status"] == "ok"}
        meets = [r for r in ok.values() if r["actual_error"] <= acc]
        best = min(meets, key=lambda r: r["wall_s"]) if meets else None
        oracle_s += best["wall_s"] if best else full_s
        oracle_cheap += best is not None
        pick = group[0][f"auto_{acc:g}"]
        auto_s += float(group[0][f"choose_s_{acc:g}"])
        if pick == "full" or pick not in ok:
            auto_s += full_s
        else:
            auto_s += ok[pick]["wall_s"]
            auto_cheap += 1
            held += ok[pick]["actual_error"] <= acc
            both += best is not None
    n = len(by_scen)
    return dict(accuracy=acc, scenarios=n, auto_wall_s=auto_s, oracle_wall_s=oracle_s,
                auto_over_oracle=auto_s / oracle_s if oracle_s > 0 else None, auto_cheaper=auto_cheap,
                oracle_cheaper=oracle_cheap, auto_cheaper_within_accuracy=held,
                auto_share=both / oracle_cheap if oracle_cheap else None)


# ---- chart ---------------------------------------------------------------------------------------------------

def chart(rows: list[dict], path: Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [r for r in rows if r["status"] == "ok"]
    groups = sorted({(r["system"], r["fidelity"]) for r in ok})
    def claims(r):
        return r["estimate"] != "" and math.isfinite(r["estimate"])

    bare = [g for g in groups if any((r["system"], r["fidelity"]) == g and not claims(r) for r in ok)]
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), gridspec_kw=dict(width_ratios=[3, 2]))
    ax, bx = axes
    markers = {"averaged": "o", "closed": "s", "linear": "^"}
    colors = {"moving_mass": "tab:blue", "spherical_pendulum": "tab:red", "wheel": "tab:green"}
    lo, hi = math.inf, 0.0
    for i, (system, fid) in enumerate(groups):
        g = [r for r in ok if (r["system"], r["fidelity"]) == (system, fid)]
        with_est = [r for r in g if claims(r)]
        without = [r for r in g if not claims(r)]
        style = dict(marker=markers.get(fid, "D"), color=colors.get(system, f"C{i}"), alpha=0.7, linestyle="none")
        if with_est:
            x = [max(r["estimate"], 1e-16) for r in with_est]
            y = [max(r["actual_error"], 1e-16) for r in with_est]
            ax.plot(x, y, label=f"{system} / {fid} (n={len(with_est)})", **style)
            lo, hi = min(lo, *x, *y), max(hi, *x, *y)
        if without:
            y = [max(r["actual_error"], 1e-16) for r in without]
            j = bare.index((system, fid))
            bx.plot(np.full(len(y), j) + np.linspace(-0.2, 0.2, len(y)), y, label=f"{system} / {fid} (n={len(y)})",
                    **style)
    if hi > 0:
        ax.plot([lo / 2, hi * 2], [lo / 2, hi * 2], "k--", lw=1, label="actual = estimate")
    ax.set(xscale="log", yscale="log", xlabel="stated estimate (rad)", ylabel="actual max |theta - theta_full| (rad)",
           title="with an estimate: above the line = estimate does not hold")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    bx.set(yscale="log", xticks=range(len(bare)), xlim=(-0.6, len(bare) - 0.4),
           ylabel="actual max |theta - theta_full| (rad)", title="no estimate, or no claim (inf): auto runs full")
    bx.set_xticklabels([f"{s}\n{f}" for s, f in bare], fontsize=8)
    bx.grid(True, which="both", alpha=0.3)
    fig.suptitle(textwrap.fill(title, 150))  # a long command would run off the page
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---- summary and main ---------------------------------------------------------------------------------------

def summary(rows: list[dict]) -> dict:
    """Per system and fidelity: the worst actual/estimate, the median estimate/actual over the rows with a finite
    estimate, the rows where the estimate claims nothing (inf) or is missing; auto against the oracle."""
    out: dict = {"groups": {}}
    ok = [r for r in rows if r["status"] == "ok"]
    for system, fid in sorted({(r["system"], r["fidelity"]) for r in ok}):
        g = [r for r in ok if (r["system"], r["fidelity"]) == (system, fid)]
        finite = [r for r in g if r["estimate"] != "" and math.isfinite(r["estimate"])]
        ratios = [r["actual_error"] / r["estimate"] if r["estimate"] > 0 else math.inf for r in finite]
        over = [r["estimate"] / r["actual_error"] for r in finite if r["actual_error"] > 0]
        inside = [r for r in g if _flag(r.get("inside", ""))]
        out["groups"][f"{system}/{fid}"] = dict(
            n=len(g), finite_estimate=len(finite), no_claim=sum(r["estimate"] == math.inf for r in g),
            no_estimate=sum(r["estimate"] == "" for r in g),
            worst_actual_over_estimate=max(ratios) if ratios else None,
            median_estimate_over_actual=float(np.median(over)) if over else None,
            over_estimate_percentiles={str(q): float(np.percentile(over, q)) for q in PERCENTILES} if over else None,
            inside=len(inside),
            coverage_inside=(sum(r in finite for r in inside) / len(inside)) if inside else None,
            over_1=sum(x > 1 for x in ratios), median_actual=float(np.median([r["actual_error"] for r in g])))
    scen = {r["index"]: r for r in rows}
    ran = {r["index"]: r for r in ok}
    out["scenarios"] = len(scen)
    out["ran"] = len(ran)
    out["failed_rows"] = sum(r["status"] == "failed" for r in rows)
    out["nan_rows"] = sum(r["status"] == "nan" for r in rows)
    out["auto_cheaper_default"] = sum(r["auto_fidelity"] not in ("full", "") for r in scen.values())
    out["shortened"] = sum("shortened" in str(r.get("note", "")) for r in scen.values())
    out["oracle"] = [oracle(rows, acc) for acc in ACCURACIES]
    out["oracle_by_system"] = {system: [oracle(rows, acc, system) for acc in ACCURACIES]
                               for system in sorted({r["system"] for r in rows})}
    return out


PERCENTILES = (10, 25, 50, 75, 90, 100)  # of estimate/actual, per system and fidelity (summary)


def _flag(x) -> bool:
    """A CSV's True/False (or a bool) as a bool."""
    return x is True or x == "True"


def rescore(rows: list[dict]) -> list[dict]:
    """The rows of a study with today's estimates, auto's picks and ``inside``, the runs' measurements (actual
    error, wall times) kept: a new estimate is scored on a study's scenarios without running any model again.
    Each scenario is read back from its ``scenario`` column (the horizon as run, shortened or not)."""
    import physics

    out, done = [], {}
    for r in rows:
        r = dict(r)
        if r["index"] not in done:
            sc = physics.Scenario.from_dict(json.loads(r["scenario"]))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                done[r["index"]] = (physics.derived(sc), auto_picks(sc), inside_conditions(sc))
        d, picks, inside = done[r["index"]]
        r.update(picks, inside=inside, auto_fidelity=d.get("auto_fidelity", ""))
        key = f"{r['fidelity']}_error_bound"
        if r["fidelity"] not in ("", "full"):
            est = float(d[key]) if key in d else None
            r.update(estimate="" if est is None else est, estimate_key=key if est is not None else "")
            if r["status"] == "ok":
                r["ratio"] = "" if est is None else (r["actual_error"] / est if est > 0 else math.inf)
        out.append(r)
    return out


def read_rows(path: Path) -> list[dict]:
    """A study's CSV with its numbers as floats ("inf" an inf: a model that claims nothing) and its flags kept."""
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        for k in ("actual_error", "estimate", "wall_s", "wall_full_s", "choose_s_0.01", "choose_s_0.001", "ratio"):
            if r.get(k, "") != "":
                r[k] = float(r[k])
        r["index"] = int(r["index"])
    return rows


def write(rows: list[dict], meta: dict, out: Path, img: Path, stem: str, title: str) -> dict:
    """The CSV, the meta JSON (with the summary) and the chart of a study's rows."""
    out.mkdir(parents=True, exist_ok=True)
    with (out / f"{stem}.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in COLUMNS})
    chart(rows, img / f"{stem}.png", title)
    meta = dict(meta, summary=summary(rows))
    (out / f"{stem}.meta.json").write_text(json.dumps(meta, indent=2, default=str))
    return meta


def run(n: int, seed: int, quick: bool, out: Path, img: Path, workers: int, command: str,
        system: str | None = None) -> dict:
    start = time.perf_counter()
    cases = draw(seed, n, system)
    if system is not None and system not in OWN_SETS:  # the same draws as the whole study, only this system's
        cases = [c for c in cases if c[1]["system"] == system]
    jobs = [(i, data, desc, MAX_STEPS[quick]) for i, (data, desc) in enumerate(cases)]
    rows: list[dict] = []
    if workers > 1:
        with ProcessPoolExecutor(workers) as pool:
            for r in pool.map(run_case, jobs):
                rows.extend(r)
    else:
        for job in jobs:
            rows.extend(run_case(job))
            print(f"  scenario {job[0] + 1}/{len(jobs)}: {rows[-1]['system']} {rows[-1]['status']}", flush=True)
    stem = (OWN_SETS[system][1] if system in OWN_SETS else "fidelity") + ("_quick" if quick else "")
    meta = dict(command=command, quick=quick, n=n, seed=seed, workers=workers,
                max_full_steps=MAX_STEPS[quick], date=datetime.now(UTC).isoformat(timespec="seconds"),
                machine=machine(), wall_total_s=time.perf_counter() - start)
    return write(rows, meta, out, img, stem, f"cheaper fidelities against the full model: {len(cases)} scenarios, "
                                             f"seed {seed} ({command})")


def rescore_file(path: Path, out: Path, img: Path, stem: str, command: str) -> dict:
    """``--rescore``: a study's CSV (and its meta JSON beside it, for the seed and the run's own record) scored
    again with today's estimates, written as ``<out>/<stem>.{csv,meta.json}`` and ``<img>/<stem>.png``."""
    rows = rescore(read_rows(path))
    source = path.with_suffix(".meta.json")
    before = json.loads(source.read_text()) if source.exists() else {}
    # a study rescored before keeps the record of the run that measured it, not of the earlier rescoring
    ran = before.get("rescored_from") or dict((k, before.get(k)) for k in ("command", "seed", "n", "date"))
    meta = dict(command=command, rescored_from=ran,
                quick=before.get("quick", False), n=before.get("n", len({r["index"] for r in rows})),
                seed=before.get("seed"), date=datetime.now(UTC).isoformat(timespec="seconds"), machine=machine())
    return write(rows, meta, out, img, stem, f"cheaper fidelities against the full model: {meta['n']} scenarios, "
                                             f"seed {meta['seed']}, rescored ({command})")


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("fidelity", __doc__)
    ap.add_argument("--quick", action="store_true", help="40 scenarios and a lower step cap (a few minutes)")
    ap.add_argument("--n", type=bounded(int, 1, 100_000), default=None,
                    help="number of scenarios (default 300; 40 with --quick)")
    ap.add_argument("--seed", type=bounded(int, 0, 2**32 - 1), default=15,
                    help="random seed of the scenario set (default 15)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results", help="CSV and meta JSON folder")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img", help="chart folder")
    ap.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    ap.add_argument("--system", choices=("moving_mass", "spherical_pendulum", *OWN_SETS),
                    default=None, help="run only this system's scenarios of the drawn set; wheel and "
                                       "quadratic_friction (the moving mass against quadratic friction): their own "
                                       "sets, written to fidelity_wheel[_quick].csv, fidelity_quadratic[_quick].csv")
    ap.add_argument("--rescore", type=Path, default=None, metavar="CSV",
                    help="score a study's CSV again with today's estimates and auto, without running any model "
                         "(the actual errors and wall times are the CSV's); writes <out>/<stem>.csv")
    ap.add_argument("--stem", default="fidelity_rescored", help="file name stem for --rescore "
                                                                   "(default fidelity_rescored)")
    a = ap.parse_args(argv)
    command = " ".join(["python -m bench fidelity", *(argv if argv is not None else [])])
    if a.rescore is not None:
        if not a.rescore.is_file():
            ap.error(f"--rescore must name a study's CSV file, got {a.rescore}")
        meta = rescore_file(a.rescore, a.out, a.img, a.stem, command)
        print(json.dumps(meta["summary"], indent=2, default=str))
        return 0
    n = a.n if a.n is not None else (40 if a.quick else 300)
    from physics.scenario.arguments import MAX_WORKERS

    if not 1 <= a.workers <= MAX_WORKERS:
        ap.error(f"--workers must be from 1 to {MAX_WORKERS}, got {a.workers}")
    meta = run(n, a.seed, a.quick, a.out, a.img, a.workers, command=command, system=a.system)
    print(json.dumps(meta["summary"], indent=2, default=str))
    return 0
