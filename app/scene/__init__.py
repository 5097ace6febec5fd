"""One tab's 3-D scene in viser: the body and its parts, the arrows and their labels, the legend, the momentum
sphere and compare mode's second body. It draws what an engine's frame says (``app.engine``) and holds no
state of the run; the panel and the replay recorder are above it.
"""
