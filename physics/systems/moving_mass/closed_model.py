"""The moving-mass system in closed form: seed 004 (10), (13) and seed 000 (2.9)-(2.11).

The formulas live in physics/closed*.py; this wraps them as a registered model. Attitude and
angular velocity are reconstructed from the closed-form G(t), theta(t) (see closed_form_state).
"""

from __future__ import annotations

import numpy as np

from physics.core.trajectory import Trajectory
from physics.registry import Model, register
from physics.scenario.scenario import Scenario
from physics.systems.moving_mass.closed_restart import restart_closed
from physics.systems.moving_mass.coefficients import coefficients


def solve_closed(sc: Scenario, t: np.ndarray) -> Trajectory:
    from physics.systems.moving_mass.closed import closed_form_state

    st = closed_form_state(np.asarray(t, dtype=float), coefficients(sc))
    t_out = np.asarray(st.get("t", t[: len(st["theta"])]), dtype=float)
    info = {"method": "closed form", "nfev": 0, "steps": 0}
    if st.get("t_stop") is not None:
        info.update(stop_reason="braking brought |G| to zero", t_stop=float(st["t_stop"]))
    else:
        info.update(stop_reason="reached t_end", t_stop=float(t_out[-1]))
    return Trajectory(t=t_out, theta=st["theta"], K=st["G"], E=st["E"], omega=st["omega"], quat=st["quat"],
                      info=info)


CLOSED = register(Model(
    name="moving_mass/closed", system="moving_mass", fidelity="closed",
    summary="closed forms: G(t) eq. (10), theta from eq. (13) or seed 000 (2.11), attitude by quadrature",
    solve=solve_closed,
    proxy="averaged",  # its rows read as the averaged model's state: K = J* omega, the theory's momentum
    restart=restart_closed,
))
