"""PNG figures of a study: hit rates with intervals, ECDFs of gaps, of evaluations and
of seconds to target, anytime curves (gap against seconds) and convergence curves.

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
from .anytime import GRID
from .store import TARGETS
from .summary import target_column
from .table import doc_groups, numeric

GAP_FLOOR = 1e-6  # gaps are drawn on a log axis; a hit sits at this floor


def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] | None = None,
             layout: str | None = None, **kwargs: Any) -> tuple[Figure, Any]:
    """``(figure, axes)`` like ``pyplot.subplots`` (``figsize`` in inches, ``layout`` as
    matplotlib's), on a ``Figure`` that no backend or pyplot state holds."""
    fig = Figure(figsize=figsize, layout=layout)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def save(fig: Figure, path: str) -> str:
    """Write a PNG and a PDF beside it atomically (:func:`~hga_jax.host.plots.save_figure`);
    return ``path`` (the PNG's)."""
    save_figure(fig, path, vector=True)
    return path


def _colours(n: int):
    """``n`` distinct colours: tab10's, then (beyond 10) tab20's light shades."""
    if n <= 10:
        cmap = matplotlib.colormaps["tab10"]
        return [cmap(i) for i in range(n)]
    cmap = matplotlib.colormaps["tab20"]
    order = list(range(0, 20, 2)) + list(range(1, 20, 2))
    return [cmap(order[i % 20]) for i in range(n)]


def _lines(configs: list[str]) -> dict[str, dict[str, Any]]:
    """A line style per configuration, every one told apart: tab10's colours, solid
    for the first ten, then dashed, dotted and dash-dotted (40 in all, then again)."""
    cmap = matplotlib.colormaps["tab10"]
    dashes = ("-", "--", ":", "-.")
    return {c: {"color": cmap(i % 10), "ls": dashes[(i // 10) % 4]}
            for i, c in enumerate(configs)}


def panels(count: int, height: float = 2.4):
    """A figure a journal page wide (7.2 in) with ``count`` panels, at most three a row,
    sharing both axes; returns ``(figure, axes)`` with the unused axes hidden."""
    cols = min(3, max(count, 1))
    rows = -(-max(count, 1) // cols)
    fig, axes = subplots(rows, cols, figsize=(7.2, 1.3 + height * rows), sharex=True,
                         sharey=True, squeeze=False, layout="constrained")
    flat = list(axes.flat)
    for ax in flat[count:]:
        ax.set_visible(False)
    return fig, flat[:count]


def _style(ax, title: str, xlabel: str, xlog: bool = True) -> None:
    """One panel of a grid: log x axis, small title, ticks and label, light grid."""
    if xlog:
        ax.set_xscale("log")
    ax.set_title(title, fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)
    ax.set_xlabel(xlabel, fontsize=8)


def _finish(fig, axes, handles: dict, ylabel: str, title: str, path: str) -> str:
    """The y label on each row's first panel, a title, one legend below, saved."""
    for a in axes[::3]:
        a.set_ylabel(ylabel, fontsize=8)
    fig.suptitle(title, fontsize=8)
    if handles:
        fig.legend(list(handles.values()), list(handles), loc="outside lower center",
                   ncol=min(3, len(handles)), fontsize=7)
    return save(fig, path)


def hit_rates(rows: list[dict[str, Any]], path: str) -> str:
    """Hit rate with its 95% Wilson interval, one row per configuration and one marker
    colour per group (family and size), in one panel."""
    groups = list(dict.fromkeys(r["group"] for r in rows))
    configs = list(dict.fromkeys(r["config"] for r in rows))
    fig, ax = subplots(figsize=(7.2, 1.3 + 0.3 * len(configs) * max(1, len(groups)) ** 0.5),
                       layout="constrained")
    step = 0.7 / max(len(groups), 1)
    for k, (group, colour) in enumerate(zip(groups, _colours(len(groups)))):
        rs = {r["config"]: r for r in rows if r["group"] == group}
        y = np.arange(len(configs)) + (k - (len(groups) - 1) / 2) * step
        rate = np.array([rs[c]["hit_rate"] if c in rs else np.nan for c in configs])
        lo = np.array([rs[c]["hit_rate_ci_low"] if c in rs else np.nan for c in configs])
        hi = np.array([rs[c]["hit_rate_ci_high"] if c in rs else np.nan for c in configs])
        ax.errorbar(100 * rate, y, xerr=100 * np.array([rate - lo, hi - rate]), fmt="o", ms=4,
                    capsize=2, color=colour, label=group)
    ax.set_yticks(np.arange(len(configs)), configs, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlim(-3, 103)
    ax.set_xlabel("runs reaching the optimum (%), 95% Wilson interval", fontsize=8)
    ax.tick_params(axis="x", labelsize=7)
    ax.grid(alpha=0.3)
    if len(groups) > 1:
        fig.legend(loc="outside lower center", ncol=min(3, len(groups)), fontsize=7)
    else:
        ax.set_title(groups[0], fontsize=8)
    return save(fig, path)


def gap_ecdf(table: pd.DataFrame, configs: list[str], path: str) -> str:
    """ECDF of the final gaps, one panel per group (shared axes, one legend); gaps below
    the axis's left end (hits among them) are counted there, infeasible runs never."""
    group, config = table["group"].to_numpy(), table["config"].to_numpy()
    groups = list(dict.fromkeys(group.tolist()))
    fig, axes = panels(len(groups))
    gap = 100 * numeric(table, "gap")
    grid = np.logspace(np.log10(100 * GAP_FLOOR), 2, 300)  # 0.01% to 100%
    lines = _lines(configs)
    handles = {}
    for ax, g in zip(axes, groups):
        for c in configs:
            m = (group == g) & (config == c)
            if m.any():
                (line,) = ax.step(grid, stats.ecdf(np.maximum(gap[m], grid[0]), grid),
                                  where="post", **lines[c], label=c, lw=1.2)
                handles[c] = line
        _style(ax, g, "final gap to the optimum (%)")
    return _finish(fig, axes, handles, "fraction of runs within", "Final gaps (left end: gap "
                   "under 0.01%, hits included; infeasible runs never count)", path)


def evaluations_ecdf(table: pd.DataFrame, configs: list[str], path: str) -> str:
    """ECDF of the evaluations a run needs to reach each target gap (the COCO view:
    configurations at equal evaluations); one row of panels per group, shared axes.
    Solvers that count no evaluations (OMPL, the exact solver) are left out."""
    evals = numeric(table, "evaluations")
    config = table["config"].to_numpy()
    configs = [c for c in configs if np.all(np.isfinite(evals[config == c]))]  # counted
    top = max((float(evals[config == c].max()) for c in configs), default=1.0)
    targets = [(numeric(table, target_column(t)),
                "the optimum" if t == 0 else f"within {100 * t:g}%") for t in TARGETS]
    return _ecdf_panels(table, configs, targets, np.logspace(1, np.log10(max(top, 100)), 400),
                        "evaluations", True, path)


def _ecdf_panels(table: pd.DataFrame, configs: list[str], targets, grid, xlabel: str,
                 xlog: bool, path: str) -> str:
    """ECDFs of per-run values (``targets``: (values, title) per column of panels) for
    each configuration; one row of panels per group, shared axes, one legend."""
    group, config = table["group"].to_numpy(), table["config"].to_numpy()
    groups = list(dict.fromkeys(group.tolist()))
    fig, axes = subplots(len(groups), len(targets), figsize=(7.2, 1.2 + 2.5 * len(groups)),
                         sharex=True, sharey=True, squeeze=False, layout="constrained")
    lines = _lines(configs)
    handles = {}
    for i, (row, g) in enumerate(zip(axes, groups)):
        for ax, (values, title) in zip(row, targets):
            for c in configs:
                m = (group == g) & (config == c)
                if m.any():
                    (line,) = ax.step(grid, stats.ecdf(values[m], grid), where="post",
                                      **lines[c], label=c, lw=1.2)
                    handles[c] = line
            _style(ax, f"{g}: {title}", xlabel if i == len(groups) - 1 else "", xlog)
        row[0].set_ylabel("fraction of runs", fontsize=8)
    return _finish(fig, [], handles, "", "", path)


def convergence(docs: list[dict[str, Any]], configs: list[str], path: str) -> str:
    """Median best-so-far penalised length over the optimum against evaluations (log
    axes), median over runs, then over a group's scenes; one panel per group."""
    labels = doc_groups(docs)
    docs = [dict(d, family=g) for d, g in zip(docs, labels)]  # grouped by family and size
    groups = list(dict.fromkeys(labels))
    fig, axes = panels(len(groups))
    lines = _lines(configs)
    handles = {}
    for ax, group in zip(axes, groups):
        for c in configs:
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
            (line,) = ax.plot(pop * (np.arange(len(med)) + 1), 100 * np.maximum(med, GAP_FLOOR),
                              **lines[c], label=c, lw=1.2)
            handles[c] = line
        ax.set_yscale("log")
        _style(ax, group, "evaluations")
    return _finish(fig, axes, handles, "best so far, % over the optimum", "Convergence: "
                   "penalised length of the best so far (median over runs, then scenes; the "
                   "floor 1e-4 % is the optimum)", path)


def anytime(docs: list[dict[str, Any]], configs: list[str], path: str) -> str:
    """Gap against seconds of a run (one core, log axis), median and quartiles over
    runs, then the median over a family's scenes; one panel per family, shared axes."""
    labels = doc_groups(docs)
    docs = [dict(d, family=g) for d, g in zip(docs, labels)]  # grouped by family and size
    groups = list(dict.fromkeys(labels))
    fig, axes = panels(len(groups))
    lines = _lines(configs)
    handles, lowest, times = {}, 0.0, []
    for ax, group in zip(axes, groups):
        for c in configs:
            ds = [d for d in docs if d["family"] == group and d["config"] == c
                  and "anytime_gap" in d["curves"]]
            if not ds:
                continue
            q = np.array([[[np.inf if v is None else v for v in row]
                           for row in d["curves"]["anytime_gap"]] for d in ds], np.float64)
            q = 100 * np.median(q, axis=0)  # over scenes: (3, len(GRID)), in %
            end = max(max(v for v in d["columns"]["time_s"] if v is not None) for d in ds)
            keep = GRID <= end * 1.0001  # a run's answer is drawn until the runs end
            q[:, ~keep] = np.nan
            q[~np.isfinite(q)] = np.nan
            if np.any(np.isfinite(q)):
                lowest = min(lowest, float(np.nanmin(q)))
                times += [float(GRID[keep][0]), float(end)] if keep.any() else []
            if ds[0].get("solver") == "exact":  # one answer, at its solve time
                (line,) = ax.plot([end], [0.0], "*", color=lines[c]["color"], ms=9, label=c)
                times.append(end)
                handles[c] = line
                continue
            (line,) = ax.plot(GRID, q[1], **lines[c], lw=1.3, label=c)
            ax.fill_between(GRID, q[0], q[2], color=lines[c]["color"], alpha=0.15, lw=0)
            handles[c] = line
        ax.axhline(0, color="0.4", lw=0.6, ls=":")
        ax.set_yscale("symlog", linthresh=0.1)
        _style(ax, group, "seconds of one run (one core)")
    ax = axes[0]
    ax.set_ylim(bottom=min(-0.02, 1.5 * lowest))
    ax.set_xlim(*((min(times) / 1.5, max(times) * 1.5) if times else (1e-4, 1.0)))
    return _finish(fig, axes, handles, "gap to the optimum (%)", "Gap held after t seconds: "
                   "median and quartiles over runs, median over scenes\n(above the plot: no "
                   "feasible path yet; below 0: shorter than the optimum)", path)


def time_to_target(table: pd.DataFrame, configs: list[str], path: str) -> str:
    """ECDF of the seconds a run needs to come within 1% of the optimum and to hit it
    (one core, log axis); one row of panels per group, shared axes."""
    secs = [(numeric(table, name) if name in table else np.full(len(table), np.inf), title)
            for name, title in (("time_1pct", "within 1% of the optimum"),
                                ("time_hit", "the optimum (gap < 1e-6)"))]
    finite = np.concatenate([v[np.isfinite(v)] for v, _ in secs] + [np.ones(1)])
    grid = np.logspace(np.log10(max(finite.min(), 1e-6)) - 0.2,
                       np.log10(finite.max()) + 0.2, 300)
    return _ecdf_panels(table, configs, secs, grid, "seconds of one run (one core)", True,
                        path)


def all_figures(table: pd.DataFrame, docs: list[dict[str, Any]], rows: list[dict[str, Any]],
                configs: list[str], folder: str) -> list[str]:
    os.makedirs(folder, exist_ok=True)
    j = lambda name: os.path.join(folder, name)  # noqa: E731 (PNG; a PDF is written beside)
    out = [hit_rates(rows, j("hit_rate.png")), gap_ecdf(table, configs, j("gap_ecdf.png")),
           evaluations_ecdf(table, configs, j("evaluations_ecdf.png")),
           time_to_target(table, configs, j("time_ecdf.png")),
           anytime(docs, configs, j("anytime.png")),
           convergence(docs, configs, j("convergence.png"))]
    return out
