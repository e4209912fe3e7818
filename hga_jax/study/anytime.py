"""Anytime behaviour of any solver: its gap as time goes on, and its time to a target gap.

Every solver of a study (:mod:`hga_jax.study.solvers`) leaves, per run, a *trace*:
the times (seconds of that run's own search, compile excluded) at which it held a
new answer, and the gap of that answer to the optimum (``inf`` while it holds no
feasible answer; a gap may be negative when a peer's path is shorter than the
tight-rope optimum). From traces this module keeps, per cell,

- the gap quartiles over runs at each time of :data:`GRID` (a step function: a run
  holds its last answer until the next), which the anytime figure draws;
- per run, the first time its gap is at most each target (None: never), which the
  time-to-target ECDFs draw.

Times are per run and single-core (docs/studies.md): a batched GA run's share of its
batch's core-seconds, a run alone's wall time, a peer's wall time.
"""
from __future__ import annotations

import numpy as np

GRID = np.logspace(-5, 3, 97)
"""Times (s) at which a cell's anytime quartiles are kept: 10 us to 1000 s, 12 per decade."""
QUARTILES = (25, 50, 75)
SLACK = 1e-6  # relative: a gap within this of a target reaches it (and of 0: a hit)


def quartiles(times: np.ndarray, gaps: np.ndarray) -> list[list[float]]:
    """Gap quartiles over runs at each time of :data:`GRID` (3 lists of ``len(GRID)``).

    ``times``: (K,) shared by every run, or (K, R) per run, increasing along K;
    ``gaps``: (K, R), the gap held from that time on (inf: none feasible yet). Before
    its first time a run holds nothing (inf). Quartiles use the nearest run's value,
    so they are runs' gaps (finite or inf), never interpolated between them."""
    gaps = np.asarray(gaps, np.float64)
    times = np.asarray(times, np.float64)
    k, r = gaps.shape
    if times.ndim == 1:
        times = np.broadcast_to(times[:, None], (k, r))
    held = np.full((len(GRID), r), np.inf)
    for j in range(r):
        idx = np.searchsorted(times[:, j], GRID, side="right") - 1
        held[:, j] = np.where(idx >= 0, gaps[np.maximum(idx, 0), j], np.inf)
    if r == 0:
        return [[float("inf")] * len(GRID) for _ in QUARTILES]
    return np.percentile(held, QUARTILES, axis=1, method="nearest").tolist()


def first_time(times: np.ndarray, gaps: np.ndarray, target: float) -> list[float | None]:
    """Per run the first time its gap is at most ``target`` (with :data:`SLACK`), or None."""
    gaps = np.asarray(gaps, np.float64)
    times = np.asarray(times, np.float64)
    if times.ndim == 1:
        times = np.broadcast_to(times[:, None], gaps.shape)
    ok = gaps <= target + SLACK * (1.0 + target)
    out: list[float | None] = []
    for j in range(gaps.shape[1]):
        hit = np.flatnonzero(ok[:, j])
        out.append(float(times[hit[0], j]) if len(hit) else None)
    return out
