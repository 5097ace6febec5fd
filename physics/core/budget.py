"""The step budget every run gets: read by the run's loop (physics/stepping/simulate.py), which refuses a run
whose pace would exceed it, and by ``auto`` (physics/systems/choice.py), which picks a model that fits it."""

from __future__ import annotations

# Adaptive or fixed steps per run: a few minutes of the slowest model, so that no input can hold the machine
MAX_STEPS = 20_000_000
