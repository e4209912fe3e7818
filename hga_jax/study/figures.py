"""PNG figures of a study: hit rates with intervals, ECDFs of gaps and of evaluations
(and seconds) to target, and convergence curves.

Figures are ``matplotlib.figure.Figure`` objects (no pyplot), so drawing and
saving them needs no display and leaves matplotlib's backend as the caller chose
it (the ``hga-jax`` command picks Agg; a notebook keeps its own).
"""
from __future__ import annotations

import os
from typing import Any

import matplotlib
import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from hga_jax.host.plots import save_figure
from . import stats
from .store import TARGETS
from .summary import target_column
from .table import numeric

GAP_FLOOR = 1e-6  # gaps are drawn on a log axis; a hit sits at this floor


def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] | None = None,
             layout: str | None = None, **kwargs: Any) -> tuple[Figure, Any]:
    """``(figure, axes)`` like ``pyplot.subplots`` (``figsize`` in inches, ``layout`` as
    matplotlib's), on a ``Figure`` that no backend or pyplot state holds."""
    fig = Figure(figsize=figsize, layout=layout)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def save(fig: Figure, path: str) -> str:
    """Write a PNG atomically (:func:`~hga_jax.host.plots.save_figure`); return ``path``."""
    save_figure(fig, path)
    return path


def _colours(n: int):
    cmap = matplotlib.colormaps["tab10" if n <= 10 else "tab20"]
    return [cmap(i % cmap.N) for i in range(n)]


def hit_rates(rows: list[dict[str, Any]], path: str) -> str:
    groups = list(dict.fromkeys(r["group"] for r in rows))
    configs = list(dict.fromkeys(r["config"] for r in rows))
    fig, axes = subplots(1, len(groups), figsize=(4 + 3 * len(groups), 1 + 0.35 * len(configs)),
                         sharey=True, squeeze=False)
    for ax, group in zip(axes[0], groups):
        rs = {r["config"]: r for r in rows if r["group"] == group}
        y = np.arange(len(configs))
        rate = np.array([rs[c]["hit_rate"] if c in rs else np.nan for c in configs])
        lo = np.array([rs[c]["hit_rate_ci_low"] if c in rs else np.nan for c in configs])
        hi = np.array([rs[c]["hit_rate_ci_high"] if c in rs else np.nan for c in configs])
        ax.errorbar(100 * rate, y, xerr=100 * np.array([rate - lo, hi - rate]), fmt="o",
                    capsize=3, color="tab:blue")
        ax.set_title(f"{group}: hit rate, 95% Wilson", fontsize=9)
        ax.set_xlabel("runs reaching the optimum (%)")
        ax.grid(alpha=0.3)
    axes[0][0].set_yticks(np.arange(len(configs)), configs, fontsize=7)
    axes[0][0].invert_yaxis()
    return save(fig, path)


def gap_ecdf(table: pd.DataFrame, configs: list[str], path: str) -> str:
    family, config = table["family"].to_numpy(), table["config"].to_numpy()
    groups = list(dict.fromkeys(family.tolist()))
    fig, axes = subplots(1, len(groups), figsize=(1 + 4.5 * len(groups), 4), squeeze=False)
    gap = np.maximum(numeric(table, "gap"), GAP_FLOOR)
    grid = np.logspace(-6, 0, 300)
    for ax, group in zip(axes[0], groups):
        for c, col in zip(configs, _colours(len(configs))):
            m = (family == group) & (config == c)
            if m.any():
                ax.step(grid, stats.ecdf(gap[m], grid), where="post", color=col, label=c, lw=1.2)
        _label(ax, "gap to the exact optimum (hits drawn at 1e-6)",
               "fraction of runs with gap at most x",
               f"{group}: ECDF of final gaps (infeasible runs never count)", xlog=True)
    axes[0][-1].legend(fontsize=6, loc="lower right")
    return save(fig, path)


def _label(ax, xlabel: str, ylabel: str, title: str, xlog=False, ylog=False) -> None:
    if xlog:
        ax.set_xscale("log")
    if ylog:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)


def evaluations_ecdf(table: pd.DataFrame, configs: list[str], path: str,
                     seconds: bool = False) -> str:
    """ECDF of evaluations (or, with ``seconds``, of search time: evaluations times the
    configuration's mean seconds per evaluation) to each target gap."""
    fig, axes = subplots(1, len(TARGETS), figsize=(4.5 * len(TARGETS), 4), sharey=True)
    evals, secs = numeric(table, "evaluations"), numeric(table, "time_s")
    config = table["config"].to_numpy()
    scale = {c: float(secs[m].sum() / evals[m].sum()) if seconds else 1.0
             for c in configs if (m := config == c).any()}
    top = max(float(evals[config == c].max()) * k for c, k in scale.items())
    grid = np.linspace(0, top, 400)
    for ax, t in zip(axes, TARGETS):
        e = numeric(table, target_column(t))
        for c, col in zip(configs, _colours(len(configs))):
            m = config == c
            if m.any():
                ax.step(grid, stats.ecdf(e[m] * scale[c], grid), where="post", color=col,
                        label=c, lw=1.2)
        ax.set_title("optimum (gap < 1e-6)" if t == 0 else f"within {100 * t:g}% of optimum",
                     fontsize=9)
        ax.set_xlabel("seconds of search per run" if seconds else "evaluations")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fraction of runs that reached the target")
    axes[-1].legend(fontsize=6, loc="upper left")
    return save(fig, path)


def convergence(docs: list[dict[str, Any]], configs: list[str], path: str) -> str:
    groups = list(dict.fromkeys(d["family"] for d in docs))
    fig, axes = subplots(1, len(groups), figsize=(1 + 4.5 * len(groups), 4), squeeze=False)
    for ax, group in zip(axes[0], groups):
        for c, col in zip(configs, _colours(len(configs))):
            ds = [d for d in docs if d["family"] == group and d["config"] == c]
            if not ds or "best_so_far_gap_m" not in ds[0]["curves"]:
                continue
            curves = [d["curves"]["best_so_far_gap_m"][1] for d in ds]
            # Scenes of one family may run for different generation counts (a budget
            # that grows with the obstacle count): a run's best-so-far stays after its
            # last generation, so shorter curves go on at their last value.
            longest = max(len(v) for v in curves)
            med = np.median([list(v) + [v[-1]] * (longest - len(v)) for v in curves], axis=0)
            pop = ds[0]["settings"]["population"]
            ax.plot(pop * (np.arange(len(med)) + 1), np.maximum(med, GAP_FLOOR), color=col,
                    label=c, lw=1.2)
        _label(ax, "evaluations", "best-so-far Dist_m / optimum - 1",
               f"{group}: median over runs, then over scenes", ylog=True)
    axes[0][-1].legend(fontsize=6, loc="upper right")
    return save(fig, path)


def all_figures(table: pd.DataFrame, docs: list[dict[str, Any]], rows: list[dict[str, Any]],
                configs: list[str], folder: str) -> list[str]:
    os.makedirs(folder, exist_ok=True)
    j = lambda name: os.path.join(folder, name)  # noqa: E731
    out = [hit_rates(rows, j("hit_rate.png")), gap_ecdf(table, configs, j("gap_ecdf.png")),
           evaluations_ecdf(table, configs, j("evaluations_ecdf.png")),
           evaluations_ecdf(table, configs, j("time_ecdf.png"), seconds=True),
           convergence(docs, configs, j("convergence.png"))]
    return out
