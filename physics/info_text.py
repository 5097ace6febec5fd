"""What ``python -m physics info`` prints: each derived quantity with its unit and a short meaning.

Text for people (6 significant digits, one ``name = value unit  meaning`` line each) and JSON for
programs (every float to full precision; inf and nan, which JSON lacks, as the strings "inf", "nan").
Names and equations are those of ../shared/MODELS.md and physics/derived.py.
"""

from __future__ import annotations

import json
import math

# name -> (unit, meaning) for the moving-mass system (seed 004 eq. (4), (10)-(11), (24); seed 000)
MOVING_MASS = {
    "F": ("s^2/(kg m^2)", "mass's conservative coefficient m rho^2 C/(Omega^2 A^3): shifts precession"),
    "D": ("kg m^2 s^3", "mass damper's dissipation coefficient (D < 0: the nutation decays)"),
    "L": ("kg m^2 s", "cavity's conservative coefficient"),
    "H": ("kg m^2 s", "cavity's dissipation coefficient (H > 0: the nutation decays)"),
    "P": ("m^7", "cavity shape factor 8 pi a0^7/525"),
    "Gamma1": ("1", "cavity dissipation in medium time lambda t (nan without a medium)"),
    "Gamma2": ("1", "mass dissipation in medium time lambda t (nan without a medium)"),
    "k_star": ("1", "braking against medium, b/(lambda G0) (nan: neither; inf: no medium)"),
    "T": ("s", "braking time: |G| reaches 0 (inf without braking)"),
    "G0": ("kg m^2/s", "initial |J* w|, the body's angular momentum"),
    "theta0": ("rad", "initial nutation angle between G and e3"),
    "eps": ("1", "|w0|/Omega: spin against the spring; averaging needs it small"),
    "Re": ("1", "cavity Reynolds number a0^2 |w0|/nu; Stokes flow needs it small"),
}
PENDULUM = {
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
COMMON = {
    "auto_fidelity": ("", "the fidelity run.fidelity = \"auto\" picks"),
    "auto_model": ("", "the model it runs"),
    "auto_method": ("", "the integrator it uses"),
    "auto_accuracy": ("rad", "run.accuracy asked for"),
    "averaged_error_bound": ("rad", "estimated error of the averaged model in theta"),
    "auto_error_bound": ("rad", "estimated error of auto's choice in theta"),
    "auto_reason": ("", ""),  # a sentence already
}


def describe(name: str, system: str) -> tuple[str, str]:
    """(unit, meaning) of a derived quantity; ("", "") when it has none on record."""
    table = MOVING_MASS if system == "moving_mass" else PENDULUM
    if name in table:
        return table[name]
    if name in COMMON:
        return COMMON[name]
    if name.startswith("omega_") and name[6:].isdigit():
        return "rad/s", f"plane pendulum {name[6:]}'s frequency (seed 002 (15))"
    if name.startswith("s_"):
        return "1/s", f"linear exponent of the {name[2:].replace('_', ' ')} mode (decay + i frequency)"
    return "", ""


def readable(value) -> str:
    """6 significant digits for a float, the text itself otherwise."""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def text_lines(values: dict, system: str) -> list[str]:
    """One ``name = value unit  meaning`` line per quantity, aligned."""
    width = max((len(k) for k in values), default=0)
    shown = {k: readable(v) for k, v in values.items()}
    vwidth = min(max((len(v) for k, v in shown.items() if k != "auto_reason"), default=0), 14)
    lines = []
    for k, v in shown.items():
        unit, meaning = describe(k, system)
        tail = f"{unit:<12}  {meaning}" if unit else meaning
        lines.append(f"{k:<{width}} = {v:<{vwidth}}  {tail}".rstrip())
    return lines


def as_json(values: dict, system: str) -> str:
    """Every quantity with its unit and meaning; floats to full precision (JSON numbers round-trip)."""
    def number(v):
        if isinstance(v, float):
            return float(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
        return v

    out = {k: {"value": number(v), "unit": describe(k, system)[0], "meaning": describe(k, system)[1]}
           for k, v in values.items()}
    return json.dumps(out, indent=1, allow_nan=False)
