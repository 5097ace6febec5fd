"""Every model registers itself on import; importing this package registers them all."""

from . import moving_mass, moving_mass_closed  # noqa: F401  (registration)
from .base import REGISTRY, Model, get_model, register

__all__ = ["REGISTRY", "Model", "get_model", "register"]
