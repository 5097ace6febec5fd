"""The pendulum nutation dampers of seed 002: Alger's spherical pendulum and Taylor's plane pendulums
(MODELS.md Part B)."""
