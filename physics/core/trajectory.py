"""The result of a run: time series in SI units, plus what produced them."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

BASE_COLUMNS = ("t", "theta", "K", "E", "wx", "wy", "wz", "qw", "qx", "qy", "qz")
FLAT = 1e-6  # relative spread below which a plotted series is drawn as constant (integration noise on |K|)


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

    def plot(self, title: str | None = None):
        """theta (rad), |K| (kg m^2/s) and E (J) against t (s), stacked on one shared time axis; returns the
        matplotlib Figure (``fig.savefig(...)`` writes it; in a notebook it is shown inline). matplotlib is
        imported here, so ``import physics`` stays light and a headless run needs no display."""
        from matplotlib.figure import Figure  # a Figure, not pyplot: no GUI backend, no global state

        fig = Figure(figsize=(7.0, 6.0), layout="constrained")
        axes = fig.subplots(3, 1, sharex=True)
        rows = ((self.theta, "theta (rad)", "tab:red"), (self.K, "|K| (kg m²/s)", "tab:green"),
                (self.E, "E (J)", "tab:blue"))
        for ax, (y, label, color) in zip(axes, rows, strict=True):
            ax.plot(self.t, y, color=color, lw=1.2)
            span, level = (float(np.ptp(y)), float(np.max(np.abs(y)))) if len(y) else (0.0, 0.0)
            if level > 0 and span <= FLAT * level:  # a conserved |K|: drawn flat, not as rounding noise magnified
                ax.set_ylim(float(np.mean(y)) - 0.05 * level, float(np.mean(y)) + 0.05 * level)
                ax.ticklabel_format(axis="y", useOffset=False)
            ax.set_ylabel(label)
            ax.grid(True, alpha=0.3)
        axes[-1].set_xlabel("t (s)")
        if title:
            fig.suptitle(title)
        return fig

    def __len__(self) -> int:
        return len(self.t)
