"""The study panels a tab opens on demand: a parameter sweep (its ranges, its chart and best point, its clickable
board in the 3-D scene) and speed versus accuracy, each run in the background and shown in a movable window,
with a mark when the scene has changed since. Built lazily by the panel (they pull in plotly).
"""
