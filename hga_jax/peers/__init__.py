"""Peers: what a study compares the HGA with, and how their paths are judged.

- :mod:`~hga_jax.peers.deap_ga`: the paper's GA written with DEAP, on the plain-Python
  decoder :mod:`~hga_jax.peers.python_decoder`;
- :mod:`~hga_jax.peers.ompl_planner`: OMPL's sampling planners in its Dubins or
  Reeds–Shepp state space;
- :mod:`~hga_jax.peers.judge`: a peer's path judged by the project's own float64 model
  (length, feasibility under the full collision rule), its waypoints joined by the
  car's shortest path (:meth:`hga_jax.model.car_model.CarModel.connect`).

Random search and the exact solver are hga-jax's own (:mod:`hga_jax.study.solvers`
runs every solver for a study). Host code; ``deap`` and ``ompl`` (the ``compare``
extra) are imported only when a peer that needs them runs.
"""
from __future__ import annotations

import importlib.util

NEEDS = {"deap": "deap", "ompl": "ompl"}
"""The package each solver needs beyond hga-jax's own dependencies."""


def missing(solver: str, planner: str | None = None) -> str | None:
    """Why ``solver`` (with ``planner``, for OMPL) cannot run here, in one line, or None."""
    package = NEEDS.get(solver)
    if package is None:
        return None
    if importlib.util.find_spec(package) is None:
        return f"{package} is not installed (pip install 'hga-jax[compare]')"
    if solver == "ompl":
        from .ompl_planner import available

        return available(planner or "")
    return None
