"""Serving the explorer: the viser server with one session (engine, panel, scene and loop thread) per browser
tab, the origin and host guard in front of it, and ``app.show`` for a notebook. The top of app.
"""
