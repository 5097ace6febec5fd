"""The moving mass of seeds 004 and 000 with its cavity, medium and braking torque (docs/models.md Part A)."""
