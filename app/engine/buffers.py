"""The sizes and names of one tab's buffers: how many rows the plots, the trail and the export keep, and what
the plots and the view can show. In one place, since the engine, its actions and its output all read them."""

SAMPLES_PER_FRAME = 4  # plot and trail rows per published frame
PLOT_POINTS = 1500  # plot window (ring buffer rows)
TRAIL_POINTS = 1200
HISTORY_ROWS = 20000  # trajectory rows the CSV export keeps from t = 0 (history.py thins them as the run goes on)
WHOLE_RUN_POINTS = 2000  # points the whole-run plots keep from t = 0: uPlot redraws them at the plots' rate
EDITS_LISTED = 5  # changes an export or a caption names one by one
# requests of one action (Play, Reset, a preset, a thrust ...) queued between two ticks at most, the oldest dropped:
# a person clicks a few times a tick at most, while a raw client's flood would otherwise be applied whole in one
# tick (10,000 Resets, each a new run); a held thruster's repeats switching thrusters are retunes too
PENDING_EACH = 8
RETUNES_KEPT = 2000  # changes the run went on through that a replay of it re-applies (beyond: from t = 0 only)
WHOLE_RUN, RECENT = "whole", "recent"  # what the plots show: the run from t = 0, or the last PLOT_POINTS rows
VIEWS = ("inertial", "body")
