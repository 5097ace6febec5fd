"""The closed forms of docs/models.md Part A (seeds 000 and 004), corrected as listed in docs/models.md A.6.

The formulas live in ``closed004`` (seed 004: braking time, G(t), the integrals I_n, the nutation angle of
eqs. (13), (24) and its exact and linearised forms, the equatorial part (18)-(23)) and ``closed000``
(seed 000: quadratic friction (2.8)-(2.11); braking with a viscous damper (3.4)-(3.9)); ``closed_state``
assembles the state of the "closed" fidelity. This module re-exports them all.
"""

from physics.systems.moving_mass.closed000 import (
                        axial_rate_35,
                        braking_momentum_34,
                        braking_nutation_38,
                        braking_omega_39,
                        braking_sigma_38,
                        braking_tau_38,
                        braking_time_34,
                        nutation_angle_37,
                        nutation_invariant_37,
                        quadratic_friction_coefficients,
                        quadratic_friction_invariant,
                        quadratic_friction_omega,
                        quadratic_friction_phi,
                        quadratic_friction_theta,
                        r_squared_rate_36,
)
from physics.systems.moving_mass.closed004 import (
                        braking_time,
                        equatorial_decay_rate,
                        equatorial_direction,
                        equatorial_modulus,
                        equatorial_phase,
                        momentum_modulus,
                        momentum_power_integral,
                        nutation_angle_13,
                        nutation_angle_24,
                        nutation_angle_D0,
                        nutation_angle_H0,
                        nutation_exponent_15,
                        nutation_first_iterate_17,
                        nutation_linear_15,
                        nutation_linear_16,
                        nutation_rate_13,
                        rotation_23,
)
from physics.systems.moving_mass.closed_state import closed_form_state

__all__ = [
    "axial_rate_35", "braking_momentum_34", "braking_nutation_38", "braking_omega_39", "braking_sigma_38",
    "braking_tau_38", "braking_time_34", "nutation_angle_37", "nutation_invariant_37",
    "quadratic_friction_coefficients", "quadratic_friction_invariant", "quadratic_friction_omega",
    "quadratic_friction_phi", "quadratic_friction_theta", "r_squared_rate_36",
    "braking_time", "equatorial_decay_rate", "equatorial_direction", "equatorial_modulus", "equatorial_phase",
    "momentum_modulus", "momentum_power_integral", "nutation_angle_13", "nutation_angle_24", "nutation_angle_D0",
    "nutation_angle_H0", "nutation_exponent_15", "nutation_first_iterate_17", "nutation_linear_15",
    "nutation_linear_16", "nutation_rate_13", "rotation_23",
    "closed_form_state",
]
