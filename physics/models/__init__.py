"""Every model registers itself on import; importing this package registers them all."""

from .. import pendulum_averaged  # noqa: F401  (registration; also sets validity.SYSTEMS)
from . import moving_mass, moving_mass_closed, pendulum  # noqa: F401  (registration)
from .base import REGISTRY, Model, get_model, register

__all__ = ["REGISTRY", "Model", "get_model", "register"]
