"""The pendulum nutation dampers of seed 002: Alger's spherical pendulum and Taylor's plane pendulums
(docs/models.md Part B)."""
