"""One tab's control panel in viser's GUI: the status line, the playbar, readouts, sliders and the notes beside
them, the live charts (uPlot) and their y scales, compare mode's folder. Callbacks only queue requests on the
engine (``app.engine``); the study windows (``app.studies``), the replay button (``app.replay``) and the Share
folder (``app.share``) are built from here but live in packages of their own, below this one.
"""
