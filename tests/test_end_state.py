"""The energy sink's end state (physics.end_state, docs/models.md "The energy sink's end state"): the textbook
case in the rigid limit, the moving mass's relative equilibrium against its closed form, the scenes with no
fixed end, and every damper's full model run until it settles, against the predicted end (the conservation
argument checked by an independent integration)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import physics
from physics.core.rotation import qconj, rotate

# The textbook case: A = B = 30, C = 60 kg m^2, spin 2 rad/s about e3, nutation 15 deg
TEXTBOOK_BODY = {"A": 30.0, "B": 30.0, "C": 60.0, "M": 100.0}
TEXTBOOK_OMEGA = [math.tan(math.radians(15.0)) * 60.0 * 2.0 / 30.0, 0.0, 2.0]  # tan theta = A w1 / (C w3)
TEXTBOOK_SPIN, TEXTBOOK_LOST = 2.0706, 8.616  # rad/s, J: the figures, to their printed digits
SPIN_TOL = 0.5e-4  # rad/s: half a unit of the printed last digit
LOST_TOL = 0.5e-3  # J: half a unit of the printed last digit
RIGID_MASS = 1e-9  # kg: a vanishing damper mass, the rigid body limit
EQUILIBRIUM_RTOL = 1e-6  # the minimiser's u against the closed form c u = m_r w^2 d_perp (its X_TOL is 1e-11)
SETTLED = 2e-3  # rad: the remaining nutation (K's angle to the predicted axis) a settled run must reach
# A run's energy above E_end with a remaining nutation theta_r: the body's share is at most
# G^2/2 (1/I_min - 1/I_max) sin^2 theta_r (E = sum K_i^2 / (2 I_i), the off-axis share of K at most sin theta_r);
# the part's own swing is of the same order, forced by the same nutation: twice the body's share bounds both.
PART_SHARE = 2.0
BELOW_TOL = 1e-9  # relative: E(t) never goes below E_end, the least energy at this |K|, but for rounding


def scenario(body: dict, part: dict, initial: dict, t_end: float = 10.0) -> physics.Scenario:
    return physics.Scenario.from_dict({"body": body, **part, "initial": initial,
                                       "run": {"t_end": t_end, "fidelity": "full", "samples": 201}})


def textbook(part: dict, t_end: float = 10.0, body: dict = TEXTBOOK_BODY, omega=None) -> physics.Scenario:
    return scenario(body, part, {"omega": omega or TEXTBOOK_OMEGA}, t_end)


def test_textbook_case_in_the_rigid_limit():
    for part in ({"mass": {"m": RIGID_MASS, "rho": 0.5, "Omega": 20.0, "chi": 5.0}},
                 {"cavity": {"beta": 1000.0, "nu": 20.0, "a0": 0.1}}):
        end = physics.end_state(textbook(part))
        assert end and end.axis_fixed and end.sign_fixed
        assert abs(end.spin - TEXTBOOK_SPIN) < SPIN_TOL
        assert abs(end.energy_to_lose - TEXTBOOK_LOST) < LOST_TOL
        assert np.allclose(end.axis, [0.0, 0.0, 1.0], atol=1e-6)
        assert end.I_max == pytest.approx(60.0, rel=1e-9)


def test_the_moving_mass_ends_in_its_relative_equilibrium():
    """A prolate body's flat spin about e1 stretches the mass (at rho e3, transverse to the spin) outward: the
    minimiser's u must solve the relative equilibrium c u = m_r |w|^2 d_perp, d = d0 e3 + u (docs/models.md)."""
    m, M, rho, Om = 5.0, 100.0, 1.0, 1.5
    sc = scenario({"A": 60.0, "B": 50.0, "C": 30.0, "M": M}, {"mass": {"m": m, "rho": rho, "Omega": Om, "chi": 1.0}},
                  {"omega": [0.6, 0.4, 2.0]})
    end = physics.end_state(sc)
    assert abs(end.axis[0]) == pytest.approx(1.0, abs=1e-9)
    eta = m / M
    m_r, d0, c = m * (1 - eta), rho / (1 - eta), m * Om**2
    uz = end.config["uz"]
    assert uz == pytest.approx(m_r * end.spin**2 * (d0 + uz) / c, rel=EQUILIBRIUM_RTOL)
    assert abs(end.config["ux"]) < EQUILIBRIUM_RTOL * uz and abs(end.config["uy"]) < EQUILIBRIUM_RTOL * uz
    # I_max: the carrier's A plus the stretched mass's m_r |d|^2 (the locked inertia about e1)
    assert end.I_max == pytest.approx(60.0 - m * rho**2 / (1 - eta) + m_r * (d0 + uz) ** 2, rel=1e-9)
    assert not end.sign_fixed  # started near the axis of least moment: above the separatrix


@pytest.mark.parametrize("part, why", [
    ({"mass": {"m": 1.0, "rho": 0.5, "Omega": 20.0, "chi": 5.0}, "control": {"b": 0.01}}, "control.b"),
    ({"mass": {"m": 1.0, "rho": 0.5, "Omega": 20.0, "chi": 5.0}, "medium": {"lambda": 0.001}}, "medium.lambda"),
    ({"mass": {"m": 1.0, "rho": 0.5, "Omega": 20.0, "chi": 0.0}}, "mass.chi = 0"),
    ({}, "no mass"),
    ({"wheel": {"J": 3.0, "c": 0.0, "axis": [1.0, 0.0, 0.0]}}, "wheel.c = 0"),
    ({"pendulum": {"m": 2.0, "l": 1.0, "h": 0.5, "k": 10.0, "c_d": 0.0}}, "pendulum.c_d = 0"),
])
def test_no_fixed_end_state_is_said_so(part, why):
    body = dict(TEXTBOOK_BODY, A=40.0, B=40.0)
    end = physics.end_state(textbook(part, body=body))
    assert not end and why in end.reason


def _plane(body_A: float) -> dict:
    return {"plane_pendulum": [{"preset": "in_plane", "m": 2.0, "l": 1.0, "k": 0.0, "c_d": 2.0, "R": 1.0, "z_p": 0.5,
                                "azimuth": a} for a in (0.0, 2 * math.pi / 3, 4 * math.pi / 3)]}


PROLATE = {"A": 60.0, "B": 50.0, "C": 30.0, "M": 100.0}
PROLATE_OMEGA = [0.6, 0.4, 2.0]
SETTLING = {  # name: (body, part, omega, t_end): each settles to SETTLED within its t_end (seconds of CPU: < 2)
    "moving mass": (TEXTBOOK_BODY, {"mass": {"m": 2.0, "rho": 1.0, "Omega": 6.0, "chi": 4.0}}, None, 200.0),
    "spherical pendulum": (dict(TEXTBOOK_BODY, A=40.0, B=40.0),
                           {"pendulum": {"m": 2.0, "l": 1.0, "h": 0.5, "k": "resonant", "c_d": 3.0}}, None, 200.0),
    "plane pendulums": ({"A": 120.0, "B": 120.0, "C": 200.0, "M": 500.0}, _plane(120.0), None, 200.0),
    "wheel": (TEXTBOOK_BODY, {"wheel": {"J": 3.0, "c": 5.0, "axis": [1.0, 0.0, 0.0]}}, None, 200.0),
    "prolate moving mass": (PROLATE, {"mass": {"m": 5.0, "rho": 1.0, "Omega": 1.5, "chi": 1.0}}, PROLATE_OMEGA,
                            2500.0),
    "prolate wheel": (PROLATE, {"wheel": {"J": 10.0, "c": 5.0, "axis": [1.0, 1.0, 1.0]}}, PROLATE_OMEGA, 400.0),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SETTLING))
def test_the_full_model_settles_in_the_predicted_end_state(name):
    body, part, omega, t_end = SETTLING[name]
    sc = textbook(part, t_end, body=body, omega=omega)
    end = physics.end_state(sc)
    tr = physics.simulate(sc)
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    K_in, _ = model.invariants(model.initial_state(sc, p)[None, :], p)
    K_body = rotate(qconj(tr.quat[-1:]), K_in)[0]
    cos = float(K_body @ end.axis) / np.linalg.norm(K_body)
    remaining = math.acos(min(1.0, abs(cos) if not end.sign_fixed else cos))
    assert remaining < SETTLED, f"{name}: K is {remaining:.3g} rad from the predicted axis at t = {t_end:g} s"
    moments = np.linalg.eigvalsh(np.diag([body["A"], body["B"], body["C"]]))
    share = end.G**2 / 2 * (1 / moments[0] - 1 / end.I_max) * math.sin(remaining) ** 2
    assert tr.E[-1] - end.E_end <= PART_SHARE * share + BELOW_TOL * end.E0
    assert np.all(tr.E >= end.E_end - BELOW_TOL * end.E0)  # the least energy at this |K|
    if name.startswith("prolate"):
        assert abs(end.axis[2]) < 1e-6  # a flat spin: the largest moment is transverse


SWUNG_TILT_TOL = 1e-7  # rad: the settled run's rates are ~1e-16, so this is the minimiser's convergence (5e-9 seen)


@pytest.mark.slow
def test_a_spherical_pendulum_without_spring_swings_out_and_tilts_the_axis():
    """With k = 0 the centrifugal force swings the bob off the spin axis (docs/models.md D.2): the end axis
    tilts from e3, by an angle the full model reaches. On a body of revolution the bob's azimuth is free, so
    the axis is fixed only in its angle to e3 (the nutation angle theta), which is what is compared."""
    sc = textbook({"pendulum": {"m": 2.0, "l": 1.0, "h": 0.5, "k": 0.0, "c_d": 3.0}}, 300.0,
                  body=dict(TEXTBOOK_BODY, A=40.0, B=40.0))
    end = physics.end_state(sc)
    tilt = math.acos(end.axis[2])
    assert tilt > 0.01  # swung out: the axis is no longer e3
    assert end.I_max > 60.0  # the bob away from the axis adds to the moment about it
    tr = physics.simulate(sc)
    assert tr.theta[-1] == pytest.approx(tilt, abs=SWUNG_TILT_TOL)
    assert tr.E[-1] == pytest.approx(end.E_end, rel=BELOW_TOL)
