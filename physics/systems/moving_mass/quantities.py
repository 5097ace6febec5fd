"""The units and meanings of the moving mass's derived quantities (``System.quantities``), for ``physics info``.

Seed 004 eq. (4), (10)-(11), (24); seed 000. The names are ``derived``'s in system.py.
"""

from __future__ import annotations

# name -> (unit, meaning)
QUANTITIES = {
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
