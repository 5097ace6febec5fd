"""The viscous wheel damper's full model (docs/models.md Part C): conservation, the linear theory it must agree
with at small nutation (the Cornell MAE4060 case), the end state the energy sink leads to, the refusals of its
table and its picture."""

from __future__ import annotations

import math

import numpy as np
import pytest

import physics
from physics.core.figure import Disk, Segment, View
from physics.systems.wheel.linear import cubic

K_RTOL = 1e-12  # relative change of the inertial K over a run: rounding and the integrator's 1e-10 steps
ENERGY_RTOL = 1e-10  # |E + W - E0| / E0: the bearing's work is all the energy lost
FREQ_RTOL = 1e-4  # nutation frequency against the cubic's root (measured 3e-6 at theta0 = 3.3e-3 rad)
DECAY_RTOL = 1e-3  # decay rate against the cubic's root (measured 8e-6)
END_E_RTOL = 1e-6  # E_end against |K|^2 / (2 I_max) after the run has settled
END_ANGLE_TOL = 1e-3  # rad: the spin axis's angle to the largest-moment axis at the end
INSIDE = 0.6  # x the body's extent: a figure's points stay within the body's drawing

# Cornell MAE4060's viscous wheel damper: Is/It = 1.5, Iw/It = 0.06, D/It = 0.5 1/s, spin 2 rad/s, It = 1 kg m^2
IT, IS, IW, D, SPIN = 1.0, 1.5, 0.06, 0.5, 2.0


def scenario(body, wheel, initial, run) -> physics.Scenario:
    return physics.Scenario.from_dict({"body": {"M": 1.0, **body}, "wheel": wheel, "initial": initial, "run": run})


def state_rows(tr) -> np.ndarray:
    return np.column_stack([tr.omega, tr.internal["phi_w"], tr.internal["Omega_w"], tr.quat, tr.internal["W_diss"]])


def test_inertial_K_is_kept_and_the_bearing_takes_all_the_energy_lost():
    sc = scenario({"A": 1.0, "B": 1.3, "C": 1.7}, {"J": 0.15, "c": 0.4, "axis": [1.0, 2.0, 2.0]},
                  {"G0": 3.0, "theta0": 0.8}, {"t_end": 50.0, "samples": 501})
    model = physics.get_model("wheel", "full")
    tr = physics.simulate(sc)
    assert tr.info["model"] == "wheel/full"
    K, E = model.invariants(state_rows(tr), model.pack(sc))
    W = tr.internal["W_diss"]
    assert np.max(np.linalg.norm(K - K[0], axis=1)) <= K_RTOL * np.linalg.norm(K[0])
    assert np.max(np.abs(E + W - E[0])) <= ENERGY_RTOL * E[0]
    assert W[-1] > 0.1 * E[0]  # the balance is tested on a run that does lose energy
    assert np.allclose(tr.E, E, rtol=1e-15, atol=0)


def cornell(c: float, **run) -> physics.Scenario:
    # theta0 = atan(It x0 / (Is n)) = 3.3e-3 rad: small enough that the linear theory is exact to ~1e-5
    return scenario({"A": IT, "C": IS}, {"J": IW, "c": c, "axis": [1.0, 0.0, 0.0]},
                    {"omega": [0.01, 0.0, SPIN]}, {"rtol": 1e-12, **run})


def nutation_root(c: float) -> complex:
    r = np.roots(cubic(IT, IS, IW, c, SPIN))
    return complex(r[np.argmax(r.imag)])


def measured_nutation(c: float, t0: float = 5.0, t1: float = 75.0) -> tuple[float, float]:
    """(frequency, decay rate) of the full model: the frequency from the upward zero crossings of K1 (one
    nutation period apart for any damped mode), the decay from the mean of log theta over windows of one period
    of |K_perp| (pi / frequency), fitted by a line: the periodic part averages out exactly over each window."""
    tr = physics.simulate(cornell(c, t_end=t1 + 5.0, samples=8001))
    k1 = IT * tr.omega[:, 0] + IW * tr.internal["Omega_w"]
    t = tr.t
    i = np.where((k1[:-1] < 0) & (k1[1:] >= 0) & (t[:-1] > t0))[0]
    crossings = t[i] - k1[i] * (t[i + 1] - t[i]) / (k1[i + 1] - k1[i])
    frequency = 2 * math.pi * (len(crossings) - 1) / (crossings[-1] - crossings[0])
    window, n = math.pi / frequency, 64
    starts = t0 + window * np.arange(int((t1 - t0) / window))
    times = (starts[:, None] + window * np.arange(n)[None, :] / n).ravel()
    theta = physics.simulate(cornell(c, t_end=t1 + 5.0, t_eval=list(times))).theta
    mean_log = np.log(theta).reshape(len(starts), n).mean(axis=1)
    decay = -np.polyfit(starts + window * (n - 1) / (2 * n), mean_log, 1)[0]
    return frequency, decay


def test_nutation_frequency_and_decay_are_the_linear_theorys_cubic_root():
    s = nutation_root(D)
    frequency, decay = measured_nutation(D)
    assert abs(frequency / s.imag - 1) <= FREQ_RTOL
    assert abs(decay / -s.real - 1) <= DECAY_RTOL
    # the tolerances discriminate: without the bearing's damping the root misses both by far
    free = nutation_root(0.0)
    assert abs(free.imag / frequency - 1) > 100 * FREQ_RTOL and abs(-free.real / decay - 1) > 100 * DECAY_RTOL


def test_the_cubic_is_the_linearized_matrix_of_the_closed_model():
    """The hand-derived cubic (A = B, a = e1) and the linear model's matrix (built from the equations for any
    body and axis) have the same roots."""
    from physics.systems.wheel.linear import BLOCK, matrix

    L = matrix(IT, IT, IS, IW, D, (1.0, 0.0, 0.0), SPIN)
    eig = np.sort_complex(np.linalg.eigvals(L[np.ix_(BLOCK, BLOCK)]))
    roots = np.sort_complex(np.roots(cubic(IT, IS, IW, D, SPIN)))
    assert np.allclose(eig, roots, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("moments, largest", [((1.0, 1.2, 1.6), 2), ((1.6, 1.3, 1.0), 0)],
                         ids=["oblate_ends_in_pure_spin", "prolate_ends_in_a_flat_spin"])
def test_the_energy_sink_ends_in_spin_about_the_largest_moment(moments, largest):
    A, B, C = moments
    sc = scenario({"A": A, "B": B, "C": C}, {"J": 0.1, "c": 0.3, "axis": [1.0, 1.0, 1.0]},
                  {"G0": 3.0, "theta0": 0.5}, {"t_end": 800.0, "samples": 201})
    tr = physics.simulate(sc)
    K = tr.K[0]
    assert abs(tr.K[-1] - K) <= K_RTOL * K * 10
    assert abs(tr.E[-1] / (K * K / (2.0 * max(moments))) - 1) <= END_E_RTOL
    spin = tr.omega[-1] / np.linalg.norm(tr.omega[-1])
    assert math.acos(min(1.0, abs(spin[largest]))) <= END_ANGLE_TOL
    assert tr.E[0] > K * K / (2.0 * max(moments)) * (1 + 100 * END_E_RTOL)  # it started away from that end


@pytest.mark.parametrize("wheel, key", [
    ({"axis": [0.0, 0.0, 0.0]}, "wheel.axis"),
    ({"axis": [1.0, float("nan"), 0.0]}, "wheel.axis"),
    ({"axis": [1.0, 0.0]}, "wheel.axis"),
    ({"c": -0.1}, "wheel.c"),
    ({"J": 0.0}, "wheel.J"),
    ({"J": 1.0}, "wheel.J"),  # J a.I^-1.a = 1 on a = e1, A = 1: the body without the wheel has no inertia there
])
def test_a_bad_wheel_is_refused_naming_its_key(wheel, key):
    data = {"body": {"A": 1.0, "C": 1.5, "M": 1.0}, "wheel": {"J": 0.06, "c": 0.5, "axis": [1.0, 0.0, 0.0], **wheel},
            "initial": {"G0": 3.0, "theta0": 0.1}, "run": {"t_end": 1.0}}
    with pytest.raises(physics.ScenarioError, match=key.replace(".", r"\.")):
        physics.Scenario.from_dict(data)


def test_the_locked_body_check_is_exact_not_min_of_the_moments():
    """J may exceed min(A, B, C) on an axis the small moment does not carry: only J a.I^-1.a < 1 matters."""
    base = {"body": {"A": 1.0, "B": 2.0, "C": 2.5, "M": 1.0}, "initial": {"G0": 3.0, "theta0": 0.1},
            "run": {"t_end": 1.0}}
    sc = physics.Scenario.from_dict({**base, "wheel": {"J": 1.5, "c": 0.1, "axis": [0.0, 0.0, 1.0]}})
    assert sc.wheel.J > min(1.0, 2.0, 2.5)
    with pytest.raises(physics.ScenarioError, match="wheel.J"):
        physics.Scenario.from_dict({**base, "wheel": {"J": 1.5, "c": 0.1, "axis": [1.0, 0.0, 0.0]}})


def test_the_axis_is_normalized_on_load_and_reads_back_as_written():
    sc = physics.Scenario.from_dict({"body": {"A": 1.0, "C": 1.5, "M": 1.0},
                                     "wheel": {"J": 0.06, "c": 0.5, "axis": [3.0, 0.0, 4.0]},
                                     "initial": {"G0": 3.0, "theta0": 0.1}, "run": {"t_end": 1.0}})
    assert sc.wheel.axis == (0.6, 0.0, 0.8)
    assert physics.Scenario.from_toml(sc.to_toml()) == sc


@pytest.mark.parametrize("state", [{}, {"phi_w": 0.0}, {"phi_w": 2.5}, {"phi_w": 1e12}, {"phi_w": math.nan},
                                   {"Omega_w": 3.0}])
def test_the_figure_is_finite_inside_the_body_and_turns_with_the_wheel(state):
    sc = physics.Scenario.from_toml(physics.get_system("wheel").example.replace("[1.0, 0.0, 0.0]", "[1.0, 2.0, 2.0]"))
    view = View(extent=2.0)
    prims = physics.get_system("wheel").figure(sc, state, view)
    disk = next(p for p in prims if p.name == "wheel")
    assert isinstance(disk, Disk) and disk.role == "wheel" and disk.colour == "wheel"
    assert any(isinstance(p, Segment) for p in prims)
    assert np.allclose(disk.normal, sc.wheel.axis) and abs(np.dot(disk.ref, disk.normal)) < 1e-15
    for p in prims:
        pts = p.points()
        assert np.all(np.isfinite(pts)) and np.max(np.linalg.norm(pts, axis=1)) <= INSIDE * view.extent
    phi = state.get("phi_w", 0.0)
    expected = math.remainder(phi, 2 * math.pi) if math.isfinite(phi) else 0.0
    assert disk.angle == pytest.approx(expected, abs=1e-12)


def test_the_figure_follows_the_runs_wheel_angle():
    sc = physics.Scenario.from_toml(physics.get_system("wheel").example)
    run = physics.LiveRun(sc)
    row = run.advance(1.0, samples=1)
    state = {k: float(v[-1]) for k, v in row.internal.items()}
    assert state["phi_w"] != 0.0
    disk = physics.get_system("wheel").figure(sc, state, View())[0]
    assert disk.angle == pytest.approx(math.remainder(state["phi_w"], 2 * math.pi))
