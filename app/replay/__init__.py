"""Offline replays: the 3-D scene recorded into one self-contained HTML file (``record``), the page around viser's
player (``page``), ``python -m app record`` (``cli``) and the panel's "Download replay" button (``export``).
Uses the scene's drawing and the engine; never the panel.
"""
