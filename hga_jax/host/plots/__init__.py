"""Figures of a run: a planned path in its scene (:mod:`.path`, its texts placed by
:mod:`.labels`; robots that move drawn by :mod:`.moving_robots`), and GA convergence
over generations (:mod:`.convergence`).

Host code on matplotlib's object API (``matplotlib.figure.Figure``, no pyplot),
so it runs headless and the figures display in notebooks. Artists carry a
``gid`` ("field", "field_inner", "obstacle", "model_circle", "turning_circle",
"start", "start_arrow", "goal", "goal_arrow", "arc", "free_arc", "line", "touched",
"optimum_path", "violation_piece", "violation_obstacle", "violation_point",
"obstacle_number", "best_median", "best_band", "mean_median", "optimum", "length_median",
"optimum_length"; among robots that move "moving_robot", "moving_model_circle",
"moving_track", "moving_start", "moving_velocity", "moving_car", "moving_gap",
"moving_collision", "time_mark", "time_label") so callers and tests can find them. Obstacles are labelled
with their numbers, counted from 1 (docs/model.md).
"""
from .convergence import headroom, plot_convergence
from .path import arc_points, plot_path, segment_points
from .style import save_figure

__all__ = ["arc_points", "headroom", "plot_convergence", "plot_path", "save_figure",
           "segment_points"]
