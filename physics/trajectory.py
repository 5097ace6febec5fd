"""The result of a run: time series in SI units, plus what produced them."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

BASE_COLUMNS = ("t", "theta", "K", "E", "wx", "wy", "wz", "qw", "qx", "qy", "qz")


@dataclass
class Trajectory:
    """Arrays over n output times.

    t (n,) s; theta (n,) rad, angle between the angular momentum and e3 (the full model uses the
    true total K, the averaged and closed forms the papers' G = J* w); K (n,) its magnitude,
    kg m^2/s; E (n,) kinetic plus spring energy, J; omega (n, 3) rad/s, body frame; quat (n, 4)
    attitude, scalar first (w, x, y, z), body -> inertial; ``internal`` maps extra column names
    (for example ux, uy, uz) to (n,) arrays. ``info`` says which model ran, why, how it ended
    (``stop_reason``, ``t_stop``) and what it cost (``nfev``, ``steps``).
    """

    t: np.ndarray
    theta: np.ndarray
    K: np.ndarray
    E: np.ndarray
    omega: np.ndarray
    quat: np.ndarray
    internal: dict[str, np.ndarray] = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    @property
    def columns(self) -> tuple[str, ...]:
        return BASE_COLUMNS + tuple(self.internal)

    def table(self) -> np.ndarray:
        """All columns side by side, shape (n, len(columns))."""
        parts = [self.t[:, None], self.theta[:, None], self.K[:, None], self.E[:, None], self.omega, self.quat]
        parts += [np.asarray(v)[:, None] for v in self.internal.values()]
        return np.hstack(parts)

    def to_csv(self, path: str | Path) -> None:
        """Write every column at full double precision (17 significant digits)."""
        np.savetxt(path, self.table(), delimiter=",", header=",".join(self.columns), comments="", fmt="%.17g")

    def slice(self, start: int, stop: int | None = None) -> Trajectory:
        """Rows start:stop, sharing info."""
        sl = np.s_[start:stop]
        return Trajectory(t=self.t[sl], theta=self.theta[sl], K=self.K[sl], E=self.E[sl], omega=self.omega[sl],
                          quat=self.quat[sl], internal={k: v[sl] for k, v in self.internal.items()},
                          info=self.info)

    def __len__(self) -> int:
        return len(self.t)
