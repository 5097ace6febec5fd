"""The units and meanings of the pendulum dampers' derived quantities (``System.quantities``, ``System.quantity``),
for ``physics info``. The names are physics/systems/pendulum/linear_general.py's ``pendulum_derived``'s.
"""

from __future__ import annotations

# name -> (unit, meaning)
QUANTITIES = {
    "W": ("rad/s", "spin rate about e3"),
    "theta0": ("rad", "initial nutation angle"),
    "K0": ("kg m^2/s", "angular momentum |K|"),
    "A_carrier": ("kg m^2", "carrier's equatorial moment (bobs removed)"),
    "B_carrier": ("kg m^2", "carrier's other equatorial moment"),
    "C_carrier": ("kg m^2", "carrier's axial moment"),
    "M_carrier": ("kg", "carrier's mass"),
    "mu": ("kg", "bob's reduced mass m (M - m)/M"),
    "D": ("m", "pivot's height above the system's centre of mass"),
    "coupling_muD2_over_A": ("1", "coupling mu D^2/A; the averaged model needs it small"),
    "omega_0": ("rad/s", "spring frequency sqrt(k/(mu l^2))"),
    "lambda_1": ("rad/s", "pendulum frequency of mode 1 in the body frame"),
    "lambda_2": ("rad/s", "pendulum frequency of mode 2 in the body frame"),
    "mode_1": ("", "sense of mode 1 relative to the spin"),
    "ct": ("1/s", "damping rate c_d/(mu l^2)"),
    "Omega": ("rad/s", "free nutation frequency in the body frame"),
    "k_tuning": ("", "how k was chosen"),
    "k": ("N m/rad", "spring stiffness used"),
    "c_d": ("N m s/rad", "pivot damper"),
    "k_resonant": ("N m/rad", "stiffness that tunes the pendulum to the nutation"),
    "decay_rate_linear": ("1/s", "slowest nutation decay rate of the linear theory (< 0: grows)"),
    "nutation": ("", "what the linear theory predicts"),
    "tau_e_linear": ("s", "time for the nutation angle to fall (or grow) by a factor e"),
}


def quantity(name: str) -> tuple[str, str] | None:
    """(unit, meaning) of a quantity named at run time, one per pendulum or mode; None for another name."""
    if name.startswith("omega_") and name[6:].isdigit():
        return "rad/s", f"plane pendulum {name[6:]}'s frequency (seed 002 (15))"
    if name.startswith("s_"):
        return "1/s", f"linear exponent of the {name[2:].replace('_', ' ')} mode (decay + i frequency)"
    return None
