"""``python -m bench corrections``: the evidence figures of docs/corrections.md, recomputed (issue 17).

Each figure is the number a test of tests/test_corrections.py or tests/test_pendulum_linear.py compares with
its margin (printed form) or tolerance (corrected form), made by the same computation: the tests' own helpers
and cases are imported, and where a test computes its comparison inline the same expression is evaluated here
on its result. Writes ``<out>/corrections.csv`` (key, value, what, test) and ``<out>/corrections.meta.json``
(command, date, machine). tests/test_corrections_quoted.py checks the page's numbers against the CSV.
"""

from __future__ import annotations

import csv
import json
import math
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from .cli import ROOT, study_parser
from .machine import machine

CORR = "tests/test_corrections.py::"
LIN = "tests/test_pendulum_linear.py::"


def _tests():
    """The test modules, imported by path: tests/ is not a package, and its helpers are the evidence."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    import tests.test_corrections as tc  # noqa: PLC0415 - only when the study runs

    return tc


def _max_abs(a, b) -> float:
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))


def seed000() -> list[tuple[str, float, str, str]]:
    """Seed 000 items 3-11, each as (key, value, what, test)."""
    tc = _tests()
    cf, rhs_25, rhs_32 = tc.cf, tc.rhs_25, tc.rhs_32
    out = []
    add = out.append
    A, C = tc.MASS["A"], tc.MASS["C"]
    d, F, Bq0 = tc._mass_coefficients(**tc.MASS)

    # item 3: (2.4)'s torque against (2.5), and (2.4) integrated against (2.11)
    t3 = CORR + "test_000_item3_eq24_k_gives_eq25"
    add(("000-3-torque-corrected", tc._relative_mismatch(tc._torque_from_k, tc._eq25_terms),
         "(2.4) torque vs (2.5), corrected, relative", t3))
    add(("000-3-torque-printed", tc._relative_mismatch(lambda w: tc._torque_from_k(w, printed=True), tc._eq25_terms),
         "(2.4) torque vs (2.5), printed, relative", t3))
    t3i = CORR + "test_000_item3_eq24_integrated_matches_eq211_only_when_corrected"
    theta, phi = tc._quadratic_closed(tc.T_000, A, C)
    w = tc.integrate(tc._k_ode(False), tc._w0_000(), tc.T_000).y
    add(("000-3-integrated-corrected-theta", _max_abs(tc.nutation_of(w, A, C), theta),
         "(2.4) integrated vs (2.11), corrected, theta, rad", t3i))
    add(("000-3-integrated-corrected-phi", _max_abs(np.unwrap(np.arctan2(w[1], w[0])), phi),
         "(2.4) integrated vs (2.11), corrected, phi, rad", t3i))
    wp = tc.integrate(tc._k_ode(True), tc._w0_000(), tc.T_000).y
    add(("000-3-integrated-printed", _max_abs(tc.nutation_of(wp, A, C), theta),
         "(2.4) integrated vs (2.11), printed, theta, rad", t3i))

    # item 4: (2.5) with the printed (2.6)
    t4 = CORR + "test_000_item4_eq26_printed_K2_and_B_fail"
    wp = tc.integrate(rhs_25, tc._w0_000(), tc.T_000,
                      (A, C, lambda w: F * A * A * (w[0] ** 2 + w[1] ** 2 + w[2] ** 2) / A,
                       lambda w: Bq0 * A**2 / C**4 * math.hypot(w[0], w[1]))).y
    add(("000-4-theta-printed", _max_abs(tc.nutation_of(wp, A, C), theta), "(2.5) with printed (2.6) vs (2.11), "
         "theta, rad", t4))
    add(("000-4-phi-printed", _max_abs(np.unwrap(np.arctan2(wp[1], wp[0])), phi), "(2.5) with printed (2.6) vs "
         "(2.11), phi, rad", t4))

    # item 5: closed (2.9)-(2.11) against (2.5)
    t5 = CORR + "test_000_item5_eq210_beta_gamma"
    K = tc.K_000
    w = tc.integrate(rhs_25, tc._w0_000(), tc.T_000,
                     (A, C, lambda w: F * (A * A * (w[0] ** 2 + w[1] ** 2) + C * C * w[2] ** 2) / A,
                      lambda w: Bq0 * math.hypot(w[0], w[1]))).y
    theta_num, phi_num = tc.nutation_of(w, A, C), np.unwrap(np.arctan2(w[1], w[0]))
    beta, gamma = cf.quadratic_friction_coefficients(A, C, F, Bq0, K)
    add(("000-5-theta-corrected", _max_abs(cf.quadratic_friction_theta(tc.T_000, tc.THETA0_000, gamma), theta_num),
         "closed (2.9)-(2.11) vs integrated (2.5), theta, rad", t5))
    add(("000-5-phi-corrected", _max_abs(cf.quadratic_friction_phi(tc.T_000, tc.THETA0_000, gamma, beta,
                                                                   tc.PHI0_000), phi_num),
         "closed (2.9)-(2.11) vs integrated (2.5), phi, rad", t5))
    beta_p = -(d + F * K * K / A) * (C / A) * K
    gamma_p = Bq0 * A**5 / C**4 * K**7
    add(("000-5-gamma-printed", _max_abs(cf.quadratic_friction_theta(tc.T_000, tc.THETA0_000, gamma_p), theta_num),
         "printed gamma vs integrated (2.5), theta, rad", t5))
    add(("000-5-beta-printed", _max_abs(cf.quadratic_friction_phi(tc.T_000, tc.THETA0_000, gamma, beta_p,
                                                                  tc.PHI0_000), phi_num),
         "printed beta vs integrated (2.5), phi, rad", t5))

    for name, c in tc.BRAKE.items():
        A, C, F, N, b, th0 = c["A"], c["C"], c["F"], c["N"], c["b"], c["theta0"]
        # item 7: |K| drift with b = 0, and (3.8) along the corrected and the printed (3.2)
        t7 = CORR + "test_000_item7_eq32_exponents"
        t = np.linspace(0, 50, 101)
        w0 = [math.sin(th0) / A, 0.0, math.cos(th0) / C]
        for printed in (False, True):
            w = tc.integrate(rhs_32, w0, t, (A, C, F, N, 0.0) + ((2, 2) if printed else ())).y
            Kn = np.hypot(A * np.hypot(w[0], w[1]), C * w[2])
            label = "printed" if printed else "corrected"
            add((f"000-7-drift-{label}-{name}", float(np.max(np.abs(Kn / Kn[0] - 1))),
                 f"relative drift of abs(K) over 50 s with b = 0, {label} (3.2), {name}", t7))
        t, T, w0, sol = tc._brake_run(c)
        sigma = cf.braking_sigma_38(1.0, b, C, N)
        theta_num = tc.nutation_of(sol.y, A, C)
        add((f"000-7-eq38-corrected-{name}", _max_abs(cf.braking_nutation_38(t / T, th0, sigma), theta_num),
             f"(3.8) vs the integrated corrected (3.2), {name}, rad", t7))
        t_p, _, _, sol_p = tc._brake_run(c, printed=True)
        add((f"000-7-eq38-printed-{name}", _max_abs(cf.braking_nutation_38(t_p / T, th0, sigma),
                                                    tc.nutation_of(sol_p.y, A, C)),
             f"(3.8) vs the integrated printed (3.2) up to 0.8 T*, {name}, rad", t7))

        # item 8: (3.6)'s left side, R'' against (R^2)' (the test's computation, inline there)
        out.extend(_item8(tc, c, name))

        # item 9: (3.7) against the integrated (3.2)
        t9 = CORR + "test_000_item9_eq37_sign_and_inertia"
        add((f"000-9-corrected-{name}", _max_abs(cf.nutation_angle_37(t, th0, 1.0, b, C, N), theta_num),
             f"(3.7) vs the integrated (3.2), {name}, rad", t9))
        x = math.tan(th0) ** 2 + math.log(math.tan(th0) ** 2) - 2 * N / (C * A**3) * cf.momentum_power_integral(
            t, 1.0, b, 0.0, 4)
        theta_printed = tc.solve_tan2_log(x)
        add((f"000-9-printed-{name}", _max_abs(theta_printed, theta_num),
             f"printed (3.7) vs the integrated (3.2), {name}, rad", t9))
        add((f"000-9-final-printed-{name}", float(theta_printed[-1]), f"theta at T* by the printed (3.7), {name}, "
             "rad", t9))
        add((f"000-9-final-{name}", float(theta_num[-1]), f"theta at T* by the integrated (3.2), {name}, rad", t9))

        # item 10: tau(theta) of (3.8), for tau <= 1/2
        t10 = CORR + "test_000_item10_eq38_exponent_and_logarithm"
        first, tau = (t / T <= 0.5) & (t > 0), t / T
        add((f"000-10-corrected-{name}", float(np.max(np.abs(tc._tau_38(theta_num, th0, sigma, 0.2, True)
                                                              - tau)[first])),
             f"(3.8) tau(theta) vs the integrated (3.2), tau <= 1/2, {name}", t10))
        add((f"000-10-exponent-printed-{name}", float(np.max(np.abs(tc._tau_38(theta_num, th0, sigma, 0.5, True)
                                                                     - tau)[first])),
             f"(3.8) with exponent 1/2 vs the integrated (3.2), tau <= 1/2, {name}", t10))
        for exponent, label in ((0.5, "both"), (0.2, "log")):
            printed = tc._tau_38(theta_num, th0, sigma, exponent, False)
            add((f"000-10-real-{label}-printed-{name}", float(np.mean(~np.isnan(printed[first]))),
                 f"share of points with a real tau, product logarithm ({label} misprints), {name}", t10))

        # item 11: (3.9) with initial phase 0.4
        t11 = CORR + "test_000_item11_eq39_general_phase"
        w = sol.y
        omega = cf.braking_omega_39(t, w0, b, A, C, F, N)
        add((f"000-11-corrected-{name}", _max_abs(omega, w.T) / float(np.max(np.abs(w))),
             f"(3.9) vs the integrated (3.2), relative to max abs(w), {name}", t11))
        wp0 = math.hypot(w0[0], w0[1])
        z = (omega[:, 0] + 1j * omega[:, 1]) / complex(w0[0], w0[1])
        amp, psi = np.abs(z), -np.angle(z)
        printed = np.column_stack([w0[0] * amp * np.cos(psi), -w0[1] * amp * np.sin(psi)])
        add((f"000-11-printed-{name}", float(np.max(np.hypot(*(printed - w[:2].T).T)) / wp0),
             f"printed (3.9) vs the integrated (3.2), relative to w_perp0, {name}", t11))
    return out


def _item8(tc, c, name):
    cf, rhs_32 = tc.cf, tc.rhs_32
    A, C, F, N, b = c["A"], c["C"], c["F"], c["N"], c["b"]
    t, T, _, sol = tc._brake_run(c, 41)
    h = 1e-4 * T

    def R_and_rate(s):
        w = sol.sol(s)
        K = math.hypot(A * math.hypot(w[0], w[1]), C * w[2])
        return w[2] / K, rhs_32(s, w, A, C, F, N, b)[2] / K + w[2] * b / K**2, K

    rhs36, left_corrected, left_printed = [], [], []
    for s in t[1:-4]:
        R, R_dot, K = R_and_rate(s)
        rhs36.append(cf.r_squared_rate_36(R, K, C, N))
        left_corrected.append(2 * R * R_dot)
        left_printed.append((R_and_rate(s + h)[1] - R_and_rate(s - h)[1]) / (2 * h))
    scale = np.max(np.abs(rhs36))
    t8 = CORR + "test_000_item8_eq36_left_side_is_d_dt_R2"
    return [(f"000-8-corrected-{name}", _max_abs(left_corrected, rhs36) / scale,
             f"(3.6) left side (R^2)' vs its right side, relative, {name}", t8),
            (f"000-8-printed-{name}", _max_abs(left_printed, rhs36) / scale,
             f"(3.6) left side R'' vs its right side, relative, {name}", t8)]


def seed004() -> list[tuple[str, float, str, str]]:
    """Seed 004 items 1-8, each as (key, value, what, test)."""
    tc = _tests()
    cf = tc.cf
    out = []
    add = out.append
    c = tc.BODY
    A, C, D, H, lam, b, G0, th0 = (c[k] for k in ("A", "C", "D", "H", "lam", "b", "G0", "theta0"))

    t1 = CORR + "test_004_item1_eq13_cos_squared"
    t, w = tc._run_004(c)
    theta_num = tc.nutation_of(w, A, C)
    add(("004-1-corrected", _max_abs(cf.nutation_angle_13(t, th0, G0, b, lam, A, C, H, D), theta_num),
         "(13) vs the integrated eq. (1), rad", t1))

    def printed_13(s, y):
        f = tc._bracket(s, G0, b, lam)
        return [f * f * math.sin(y[0]) * math.cos(y[0]) / (A * C * lam**2)
                * (-H / A + D * math.cos(y[0]) * f * f / (C**3 * lam**2))]
    add(("004-1-printed", _max_abs(tc.integrate(printed_13, [th0], t).y[0], theta_num),
         "printed (13) vs the integrated eq. (1), rad", t1))

    t7 = CORR + "test_004_item7_eq24_powers_of_G0"
    k_star = b / (lam * G0)
    add(("004-7-corrected", _max_abs(cf.nutation_angle_24(lam * t, th0, H * G0**2 / (lam * A**2 * C),
                                                          D * G0**4 / (lam * A * C**4), k_star), theta_num),
         "(24) vs the integrated eq. (1), rad", t7))
    add(("004-7-printed", _max_abs(cf.nutation_angle_24(lam * t, th0, H / (lam * A**2 * C), D / (lam * A * C**4),
                                                        k_star), theta_num),
         "printed (24) vs the integrated eq. (1), G0 = 1.5, rad", t7))

    # item 2: linearised theta near 0
    t2 = CORR + "test_004_item2_eq15_lambda_factor"
    dth0 = 1e-4
    t, w = tc._run_004(dict(c, theta0=dth0), 100)
    theta_num = tc.nutation_of(w, A, C)
    add(("004-2-corrected", float(np.max(np.abs(cf.nutation_linear_15(t, dth0, G0, b, lam, A, C, H, D)
                                                / theta_num - 1))),
         "(15) vs the integrated eq. (1), theta0 = 1e-4, relative", t2))
    E, Dc = G0 * lam + b, D / C**3
    K_printed = (0.25 * Dc * E**4 * -np.expm1(-4 * lam * t) - 4 / 3 * b * Dc * E**3 * -np.expm1(-3 * lam * t)
                 + (3 * b * b * Dc - 0.5 * H / A) * E**2 * -np.expm1(-2 * lam * t)
                 - 2 * (2 * b * b * Dc - H / A) * b * E * -np.expm1(-lam * t)
                 + (b * b * Dc / lam - H * lam / A) * b * b * t) / (A * C * lam**3)
    add(("004-2-printed", float(np.max(np.abs(dth0 * np.exp(K_printed) / theta_num - 1))),
         "printed (15) vs the integrated eq. (1), theta0 = 1e-4, relative", t2))

    # item 4: linearised near pi/2
    t4 = CORR + "test_004_item4_eq16_square"
    dth0 = -1e-4
    t, w = tc._run_004(dict(c, theta0=math.pi / 2 + dth0), 100)
    dtheta_num = tc.nutation_of(w, A, C) - math.pi / 2
    add(("004-4-corrected", float(np.max(np.abs(cf.nutation_linear_16(t, dth0, G0, b, lam, A, C, H)
                                                / dtheta_num - 1))),
         "(16) vs the integrated eq. (1), theta0 = pi/2 - 1e-4, relative", t4))
    exponent = H / (A * A * C * lam**2) * (-0.5 * E / lam * np.expm1(-2 * lam * t) + 2 * b * E / lam
                                           * np.expm1(-lam * t) + b * b * t)
    add(("004-4-printed", float(np.max(np.abs(np.log(dth0 * np.exp(exponent) / dtheta_num)))),
         "printed (16): error of the exponent", t4))

    # item 5: (17) against the first Picard iterate
    t5 = CORR + "test_004_item5_eq17_secular_sign"
    t = np.linspace(0, cf.braking_time(G0, b, lam), 200)

    def picard(s, y):
        G = tc._bracket(s, G0, b, lam) / lam
        return [G * G * math.sin(th0) * math.cos(th0) / (A * C) * (-H / A + D * G * G * math.cos(th0) ** 2 / C**3)]
    first_iterate = th0 + tc.integrate(picard, [0.0], t).y[0]
    Dc, s, co = D * math.cos(th0) ** 2 / (C**3 * lam**2), math.sin(th0), math.cos(th0)
    bracket = (0.25 * Dc * E**4 * -np.expm1(-4 * lam * t) - 4 / 3 * b * Dc * E**3 * -np.expm1(-3 * lam * t)
               + (3 * b * b * Dc - 0.5 * H / A) * E**2 * -np.expm1(-2 * lam * t)
               - 2 * b * (2 * b * b * Dc - H / A) * E * -np.expm1(-lam * t))
    secular = lam * (-H / A + b * b * Dc) * b * b * t
    add(("004-5-flipped", _max_abs(th0 + s * co * (bracket + secular) / (A * C * lam**3), first_iterate),
         "(17) with the secular sign flipped vs the first Picard iterate, rad", t5))
    add(("004-5-printed", _max_abs(th0 + s * co * (bracket - secular) / (A * C * lam**3), first_iterate),
         "printed (17) vs the first Picard iterate, rad", t5))

    # item 6: mu of a passive prolate body
    t6 = CORR + "test_004_item6_mu_can_be_negative"
    c6 = dict(A=1.0, C=0.5, F=0.03, D=0.01, L=0.01, H=-0.02, lam=0.0, b=0.0, G0=1.0, theta0=0.3)
    A6, C6, D6, L6, H6 = (c6[k] for k in ("A", "C", "D", "L", "H"))
    t, w = tc._run_004(c6, 100, t_end=40.0)
    theta = cf.nutation_angle_13(t, 0.3, 1.0, 0.0, 0.0, A6, C6, H6, D6)
    mu = cf.equatorial_decay_rate(theta, np.full_like(t, 1.0), 0.0, 0.0, A6, C6, L6, D6)
    N_num = A6 * np.hypot(w[0], w[1])
    add(("004-6-mu-min", float(np.min(mu)), "mu over 40 s, least, 1/s", t6))
    add(("004-6-mu-max", float(np.max(mu)), "mu over 40 s, greatest, 1/s", t6))
    add(("004-6-N-growth", float(N_num[-1] / N_num[0]), "integrated N at 40 s over N at 0", t6))
    add(("004-6-eq19", _max_abs(cf.equatorial_modulus(t, 0.3, 1.0, 0.0, 0.0, A6, C6, H6, D6, L6), N_num)
         / float(np.max(N_num)), "(19) vs the integrated N, relative", t6))

    t8 = CORR + "test_004_section5_final_theta_is_monotone_in_k_star"
    for k_star in tc.SECTION5_FINAL:
        add((f"004-8-final-kstar-{k_star:g}",
             float(cf.nutation_angle_24(np.array([math.log1p(1 / k_star)]), math.pi / 4, 1.0, 1.0, k_star)[0]),
             f"theta(tau_T) by (24), Gamma1 = Gamma2 = 1, theta0 = pi/4, k* = {k_star:g}, rad", t8))
    return out


def _linear():
    _tests()  # puts the repository on sys.path
    import tests.test_pendulum_linear as tl  # noqa: PLC0415 - only when the study runs

    return tl


def seed002() -> list[tuple[str, float, str, str]]:
    """Seed 002 items 1-4, 8 and 9 (tests/test_pendulum_linear.py), each as (key, value, what, test)."""
    tl = _linear()
    pl, pg = tl.pl, tl.pg
    out = []
    add = out.append
    deg = tl.deg

    # item 1: the full model's Jacobian frequencies against (6) with mu and with m
    t1 = LIN + "test_jacobian_frequencies_match_eq6_with_reduced_mass_not_m"
    k = 30.0
    sc = tl.set_R(h=-1.0, k=k, c_d=0.0)
    system = tl.pendulum_system(sc)
    lam = np.linalg.eigvals(tl.jacobian(tl.SPHERICAL, sc, 7))
    omega0 = pl.natural_frequency(k, system.mu, 1.0)
    l1, l2 = pl.pendulum_frequencies(omega0, system.W)
    Omega = pl.nutation_frequency(100.0, 150.0, system.W)
    expected = np.array([1j * l1, -1j * l1, 1j * l2, -1j * l2, 1j * Omega, -1j * Omega, 0.0])
    add(("002-1-corrected", tl.match(lam, expected), "Jacobian eigenvalues vs (6) with mu, rad/s", t1))
    printed = pl.pendulum_frequencies(pl.natural_frequency(k, 5.0, 1.0), system.W)
    add(("002-1-printed", 100 * tl.match(lam, 1j * np.array(printed)) / l1,
         "Jacobian eigenvalues vs (6) with m, % of lambda_1", t1))

    # item 2: (6)'s roots against omega_0 -+ W, the test's five cases
    t2 = LIN + "test_eq6_roots_are_omega0_minus_and_plus_W_and_eq7_gives_unit_c"
    cases = [(3.0, 2.0), (2.5, 1.0), (7.0, 0.3), (4 / 3, 2.0), (0.5, 3.0)]
    add(("002-2-roots", max(abs(r / e - 1) for o, W in cases
                            for r, e in zip(pl.frequencies_eq6(o**2 - W**2, W), (abs(o - W), o + W), strict=True)),
         "roots of (6) vs abs(omega_0 - W) and omega_0 + W, five cases, relative", t2))

    # item 3: (8)'s damping of each mode against the full model, and its frequency shift from a spring change
    t3 = LIN + "test_eq8_amplitude_equations_predict_the_full_models_damping_only_when_corrected"
    mu, c_d = 5.0 * 500.0 / 505.0, 0.2
    W, omega0, ct = 2.0, pl.natural_frequency(k, mu, 1.0), c_d / mu
    add(("002-3-omega0", omega0, "omega_0 of the set R variant (h = -1, k = 30), rad/s", t3))

    def damping(al, be, ald, bed):
        return -ct * ald, -ct * bed

    for mode in (1, 2):
        lam_j = pl.pendulum_frequencies(omega0, W)[mode - 1]
        c, a0 = (-1.0 if mode == 1 else 1.0), 1 * deg
        sc = tl.set_R(h=-1.0, k=k, c_d=c_d, theta0=0.0, t_end=60.0)
        tr = tl.run_from(tl.SPHERICAL, sc, {4: c * a0, 5: a0 * lam_j}, np.linspace(0.0, 60.0, 6001))
        amp = np.hypot(tr.internal["alpha"], tr.internal["beta"])
        add((f"002-3-mode{mode}-measured", float(np.polyfit(tr.t, np.log(amp), 1)[0]),
             f"mode {mode} swing decay rate in the full model, 1/s", t3))
        for printed in (False, True):
            label = "printed" if printed else "corrected"
            add((f"002-3-mode{mode}-{label}", tl._eq8_rates(mode, damping, W, omega0, printed=printed)[0],
                 f"mode {mode} decay rate by the {label} (8), 1/s", t3))
    t3f = LIN + "test_eq8_phase_equations_predict_the_frequency_shift_only_when_corrected"
    dk, mode = 0.03, 1

    def freq(kk):
        lam = np.linalg.eigvals(tl.jacobian(tl.SPHERICAL, tl.set_R(h=-1.0, k=kk, c_d=0.0), 7))
        target = pl.pendulum_frequencies(omega0, W)[mode - 1]
        return abs(lam[np.argmin(np.abs(np.abs(lam.imag) - target))].imag)

    def spring(al, be, ald, bed):
        return -dk / mu * al, -dk / mu * be

    measured = (freq(k + dk) - freq(k - dk)) / 2
    corrected = tl._eq8_rates(mode, spring, W, omega0, printed=False)[1]
    add(("002-3-shift-measured", measured, "mode 1 frequency shift from dk = 0.03, full-model Jacobian, rad/s", t3f))
    add(("002-3-shift-corrected", abs(corrected / measured - 1), "corrected (8)'s shift vs the measured, relative",
         t3f))
    add(("002-3-shift-printed", tl._eq8_rates(mode, spring, W, omega0, printed=True)[1],
         "printed (8)'s shift, rad/s", t3f))

    # item 4: the free-precession ellipse and (11)'s precession-frequency shift
    t4 = LIN + "test_free_precession_ellipse_is_sqrt_s2_over_s1_not_the_printed_ratio"
    add(("002-4-ratio-corrected", pl.precession_amplitude_ratio(100.0, 120.0, 150.0),
         "free-precession amplitude ratio sqrt(s2/s1), A B C = 100 120 150", t4))
    add(("002-4-ratio-printed", pl.precession_amplitude_ratio_printed(100.0, 120.0, 150.0),
         "the printed (10) ratio", t4))
    t4s = LIN + "test_eq11_predicts_the_full_models_precession_shift_only_when_corrected"
    A, B, C, dB = 100.0, 120.0, 150.0, 0.01

    def nutation(Bc):
        lam = np.linalg.eigvals(tl.jacobian(tl.SPHERICAL, tl.set_R(h=-1.0, k=30.0, c_d=0.0, B=Bc), 7))
        return lam[np.argmin(np.abs(lam - 0.7j))].imag

    measured = (nutation(B + dB) - nutation(B - dB)) / 2
    s1, s2 = pl.precession_coefficients(A, B, C)
    ds1, ds2 = -dB / A, -(C - A) * dB / B**2
    corrected = tl._eq11_frequency_shift(s1, s2, ds1, ds2, W, printed=False)
    printed = tl._eq11_frequency_shift(s1, s2, ds1, ds2, W, printed=True)
    add(("002-4-shift-measured", measured, "precession-frequency shift from dB = 0.01, full-model Jacobian, rad/s",
         t4s))
    add(("002-4-shift-corrected", corrected, "the corrected (11)'s shift, rad/s", t4s))
    add(("002-4-shift-corrected-rel", abs(corrected / measured - 1), "the corrected (11)'s shift vs the measured, "
         "relative", t4s))
    add(("002-4-shift-printed", printed, "the printed (11)'s shift, rad/s", t4s))
    add(("002-4-shift-printed-off", 100 * abs(printed / measured - 1), "the printed (11)'s shift vs the measured, %",
         t4s))

    # item 8: a plane pendulum's damping, (16) corrected and printed against the full model
    t8 = LIN + "test_eq16_plane_pendulum_damping_is_corrected_form"
    sc = tl.heavy_plane("in_plane", 1.0, 3.0, c_d=0.04)
    system = tl.pendulum_system(sc)
    mu = 2.0 * (system.M - 2.0) / system.M
    omega, ct = pg.plane_frequency(system.bobs[0], system.W, system.M), 0.04 / mu
    tr = tl.run_from(tl.PLANE, sc, {3: 2 * deg}, np.linspace(0.0, 100.0, 4001))
    amp = np.hypot(tr.internal["a1"], tr.internal["a1_dot"] / omega)
    Psi = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    G = -ct * (-omega * np.sin(Psi))
    add(("002-8-omega", omega, "the plane pendulum's frequency, rad/s", t8))
    add(("002-8-ct", ct, "its damping ct = c_d/mu, 1/s", t8))
    add(("002-8-measured", float(np.polyfit(tr.t, np.log(amp), 1)[0]), "its swing decay rate, full model, 1/s", t8))
    add(("002-8-corrected", float(np.mean(-(1 / omega) * G * np.sin(Psi))), "decay rate by the corrected (16), 1/s",
         t8))
    add(("002-8-printed", float(np.mean(G * np.cos(Psi))), "decay rate by the printed (16), 1/s", t8))

    # item 9: the plane pendulums' Jacobian frequencies against the B.7 table
    t9 = LIN + "test_plane_pendulum_frequency_follows_eq15_table_not_omega_z"
    for preset, R, k in (("in_plane", 0.5, 0.0), ("in_plane", 2.0, 3.0), ("meridian_out", 0.5, 1.0),
                         ("meridian_in", 0.5, 1.0), ("meridian_axis", 0.0, 2.0)):
        sc = tl.heavy_plane(preset, R, k)
        system = tl.pendulum_system(sc)
        mu = 2.0 * (system.M - 2.0) / system.M
        table = {"in_plane": 4 * R + k / mu, "meridian_out": 4 * (1 + R) + k / mu,
                 "meridian_in": 4 * (1 - R) + k / mu, "meridian_axis": 4 + k / mu}[preset]
        omega = pg.plane_frequency(system.bobs[0], system.W, system.M)
        lam = np.linalg.eigvals(tl.jacobian(tl.PLANE, sc, 5))
        found = float(lam[np.argmin(np.abs(lam - 1j * omega))].imag)
        key = f"002-9-{preset}-R{R:g}-k{k:g}"
        add((key, found, f"Jacobian frequency, {preset}, R = {R:g}, k = {k:g}, rad/s", t9))
        add((key + "-table", math.sqrt(table), f"B.7 table frequency, {preset}, R = {R:g}, k = {k:g}, rad/s", t9))
    return out


def seed002_runs() -> list[tuple[str, float, str, str]]:
    """Seed 002 items 5 and 6: set R's nutation decay and the resonant and prolate tunings, as
    tests/test_pendulum_full.py and tests/test_pendulum_tuning.py compute them."""
    _tests()
    import tests.test_pendulum_full as tf  # noqa: PLC0415 - only when the study runs
    import tests.test_pendulum_tuning as tt  # noqa: PLC0415

    physics, pl, deg = tf.physics, tt.pl, tf.deg
    out = []
    tr = physics.simulate(tf.set_R(1 * deg, t_end=80.0, samples=1601))
    out.append(("002-5-full-rate", tf.decay_rate(tr.t, tr.theta), "set R at 1 deg: the full model's nutation decay "
                "rate, 1/s", "tests/test_pendulum_full.py::test_set_R_nutation_decay_rate_matches_B6"))
    p = pl.spherical_linear(tt.pendulum_system(tt.set_R()))
    out.append(("002-6-resonance", abs(p.lambdas[0] / p.Omega - 1), "resonant tuning: lambda_1 vs Omega, relative",
                "tests/test_pendulum_tuning.py::test_resonant_tuning_puts_mode_1_on_the_nutation"))
    sc = physics.Scenario.load(ROOT / "assets/scenarios/pendulum_prolate.toml").with_values(**{
        "initial.theta0": 0.5 * deg, "initial.G0": 200.0 / math.cos(0.5 * deg), "run.t_end": 120.0,
        "run.samples": 2401, "run.fidelity": "full"})
    t6 = "tests/test_pendulum_tuning.py::test_prolate_damper_makes_the_nutation_grow_at_the_linear_rate"
    out.append(("002-6-prolate-linear", -pl.slowest_decay_rate(pl.spherical_linear(tt.pendulum_system(sc))),
                "prolate carrier with a damper: linear theory's nutation growth rate, 1/s", t6))
    tr = physics.simulate(sc)
    out.append(("002-6-prolate-full", float(np.polyfit(tr.t, np.log(tr.theta), 1)[0]),
                "the same, the full model's growth rate, 1/s", t6))
    return out


def pivot() -> list[tuple[str, float, str, str]]:
    """The gimbal-pole section: tests/test_pendulum_pivot.py's pole() and small() scenarios."""
    _tests()
    import tests.test_pendulum_pivot as tp  # noqa: PLC0415 - only when the study runs

    physics = tp.physics
    t_pole = ("tests/test_pendulum_pivot.py::"
              "test_isotropic_pivot_goes_through_the_pole_with_a_spring_and_keeps_the_invariants")
    sc = tp.pole("isotropic")
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    tr = physics.simulate(sc)
    angle = np.degrees(np.arccos(np.clip(tp.arm_z(tr), -1.0, 1.0)))  # the arm from e3
    over, chart = angle > 90.0, tr.internal["chart"]
    K, E = model.invariants(tp.states(tr), p)
    W = tr.internal["W_diss"]
    out = [("pivot-pole-t-end", float(tr.t[-1]), "isotropic pivot through the pole: the run's end, s", t_pole),
           ("pivot-pole-max-angle", float(angle.max()), "its arm's largest angle from e3, deg", t_pole),
           ("pivot-pole-past-90", float(np.sum(over[1:] & ~over[:-1])), "times it swings past 90 deg", t_pole),
           ("pivot-pole-switches", float(np.sum(chart[1:] != chart[:-1])), "chart switches (between samples)",
            t_pole),
           ("pivot-pole-K", float(np.max(np.linalg.norm(K - K[0], axis=1)) / np.linalg.norm(K[0])),
            "drift of the inertial K, relative", t_pole),
           ("pivot-pole-EW", float(np.max(np.abs(E[0] - E - W)) / E[0]), "drift of E + W, relative", t_pole)]
    try:
        physics.simulate(tp.pole("cardan"))
        fault_t = math.nan  # no fault: the CSV says so and the page's figure fails its test
    except tp.IntegrationFault as fault:
        fault_t = float(fault.t)
    out.append(("pivot-cardan-fault-t", fault_t, "the Cardan pivot's fault time at the pole, s",
                "tests/test_pendulum_pivot.py::test_cardan_pivot_stops_at_the_pole_and_names_the_key"))
    t_small = "tests/test_pendulum_pivot.py::test_small_swings_agree_with_the_cardan_pivot_to_third_order"
    diffs = []
    for theta0 in (0.01, 0.02):
        iso, card = physics.simulate(tp.small("isotropic", theta0)), physics.simulate(tp.small("cardan", theta0))
        diffs.append(float(np.max(np.abs(iso.theta - card.theta))))
        out.append((f"pivot-small-{theta0:g}", diffs[-1], f"isotropic vs Cardan pivot, theta0 = {theta0:g}, "
                    "max abs theta difference, rad", t_small))
    out.append(("pivot-small-order", math.log2(diffs[1] / diffs[0]), "the order of that difference in theta0",
                t_small))
    return out


# the seed tables (000, 004, 002) and the gimbal-pole section's table
PARTS = {"000": seed000, "004": seed004, "002": seed002, "002 runs": seed002_runs, "pivot": pivot}


def run(out: Path, command: str) -> Path:
    start = time.perf_counter()
    rows = [row for part in PARTS.values() for row in part()]
    out.mkdir(parents=True, exist_ok=True)
    path = out / "corrections.csv"
    with path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["key", "value", "what", "test"])
        for key, value, what, test in rows:
            writer.writerow([key, f"{value:.6g}", what, test])
    meta = dict(command=command, date=datetime.now(UTC).isoformat(timespec="seconds"), machine=machine(),
                figures=len(rows), wall_s=round(time.perf_counter() - start, 1))
    (out / "corrections.meta.json").write_text(json.dumps(meta, indent=2) + "\n")
    return path


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("corrections", __doc__)
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results",
                    help="where corrections.csv and its .meta.json go (default bench/results)")
    a = ap.parse_args(argv)
    command = "python -m bench corrections" + (f" --out {a.out}" if a.out != ROOT / "bench" / "results" else "")
    path = run(a.out, command)
    print(path)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
