"""What the readouts say about the last edit: a parameter or fidelity change keeps the angular momentum K
and the attitude (physics.carry_state) but may change the energy E, and a class should see that it did."""

from __future__ import annotations

# |dE| below this fraction of E is rounding (an edit that leaves E alone, solved to about 1e-16), not news
SHOWN_FRACTION = 1e-12
LABEL = "E changed by the edit"


def edit_readouts(dE: float | None, note: str, E: float) -> dict[str, str]:
    """Readout lines for the last edit: its energy change (None: the run restarted, or no edit yet), and
    why the state could not be kept when it was not (``note``)."""
    out: dict[str, str] = {}
    if dE is not None and abs(dE) > SHOWN_FRACTION * max(abs(E), 1e-300):
        out[LABEL] = f"{dE:+.3g} J (K and attitude kept)"
    if note:
        out["last edit"] = note
    return out
