"""The internal parts a body can carry, one registered System each (``physics.registry``).

Each folder here is one system; its ``system`` module registers it. ``physics.registry.load_builtin``
imports them all (this package's ``__init__`` stays empty so that a system's parameter tables can be
imported on their own without cycles).
"""
