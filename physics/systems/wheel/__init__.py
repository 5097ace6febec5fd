"""The viscous wheel damper: a wheel turning about a body-fixed axis in a viscous bearing (docs/models.md Part C)."""
