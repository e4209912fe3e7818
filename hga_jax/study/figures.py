"""PNG figures of a study: hit rates with intervals, ECDFs of gaps, of evaluations and
of seconds to target, anytime curves (gap against seconds) and convergence curves.

Figures are ``matplotlib.figure.Figure`` objects (no pyplot), so drawing and
saving them needs no display and leaves matplotlib's backend as the caller chose
it (the ``hga-jax`` command picks Agg; a notebook keeps its own). Each figure has a
function that draws it (``*_figure``, returning the ``Figure``) and one that saves it
(returning the PNG's path).

Nothing is hidden: long configuration names are wrapped to fit the page, every
configuration has its own colour, dash and marker (markers at sparse, staggered
points), curves that coincide are drawn widest first with the others on top and are
named in the legend's title, and every figure grows to hold its legend.
"""
from __future__ import annotations

import os
from typing import Any

import numpy as np
import pandas as pd
from matplotlib import patheffects
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.transforms import blended_transform_factory

from . import stats
from .anytime import GRID
from .figure_lines import MARKERS, Drawn, colours, proxy, styles
from .figure_page import TEXT, WIDTH, height, lines_of, save, subplots, text_width, wrap
from .store import TARGETS
from .summary import target_column
from .table import doc_groups, numeric

GAP_FLOOR = 1e-6  # gaps are drawn on a log axis; a hit sits at this floor


def panels(count: int, height: float = 2.4):
    """A figure a journal page wide (7.2 in) with ``count`` panels, at most three a row,
    sharing both axes; returns ``(figure, axes)`` with the unused axes hidden."""
    cols = min(3, max(count, 1))
    rows = -(-max(count, 1) // cols)
    fig, axes = subplots(rows, cols, figsize=(WIDTH, 1.3 + height * rows), sharex=True,
                         sharey=True, squeeze=False, layout="constrained")
    flat = list(axes.flat)
    for ax in flat[count:]:
        ax.set_visible(False)
    return fig, flat[:count]


def _panel_width(ax) -> float:
    """Inches a panel's title may take: its column's share of the page, less the tick
    labels beside it."""
    cols = ax.get_subplotspec().get_gridspec().ncols
    return (WIDTH - 0.5) / cols - 0.3


def _style(ax, title: str, xlabel: str, xlog: bool = True) -> None:
    """One panel of a grid: log x axis, small title (wrapped to the panel's width),
    ticks and label, light grid."""
    if xlog:
        ax.set_xscale("log")
    if text_width(title, 8) > _panel_width(ax):
        title = title.replace(": ", ":\n", 1)  # a group's name, then what the panel shows
    ax.set_title(wrap(title, _panel_width(ax), 8), fontsize=8)
    ax.tick_params(labelsize=TEXT)
    ax.grid(alpha=0.3)
    ax.set_xlabel(wrap(xlabel, _panel_width(ax), 8), fontsize=8)


def _legend(fig: Figure, handles: dict[str, Any], note: str = "") -> None:
    """One legend below the panels, its labels wrapped to fit its columns (one to
    three, whichever is shortest), titled ``note``; the figure grows by its height."""
    if not handles and not note:
        return
    room = WIDTH - 0.4
    pad = 0.55  # inches beside a label: its handle, the gap to it and to the next column
    best = None
    for ncol in range(1, min(3, max(len(handles), 1)) + 1):
        labels = [wrap(label, room / ncol - pad) for label in handles]
        rows = -(-len(labels) // ncol)
        tall = max((sum(lines_of(x) for x in labels[j * rows:(j + 1) * rows]) + 0.45 * len(
            labels[j * rows:(j + 1) * rows]) for j in range(ncol)), default=0.0)
        if best is None or tall <= best[0]:
            best = (tall, ncol, labels)
    tall, ncol, labels = best
    title = wrap(note, room - 0.2) if note else None
    leg = fig.legend(list(handles.values()), labels, loc="outside lower center", ncol=ncol,
                     fontsize=TEXT, title=title, title_fontsize=TEXT, alignment="left")
    if title:
        leg.get_title().set_multialignment("left")
    grow = height(tall) + (height(lines_of(title)) if title else 0.0) + 0.15
    w, h = fig.get_size_inches()
    fig.set_size_inches(w, h + grow)


def _finish(fig, axes, handles: dict, ylabel: str, title: str, note: str = "") -> Figure:
    """The y label on each row's first panel, a title (wrapped), one legend below."""
    for a in axes[::3]:
        a.set_ylabel(wrap(ylabel, 1.7, 8), fontsize=8)
    if title:
        title = wrap(title, WIDTH - 0.3, 8)
        fig.suptitle(title, fontsize=8)
        w, h = fig.get_size_inches()
        fig.set_size_inches(w, h + height(lines_of(title) - 1, 8))
    _legend(fig, handles, note)
    return fig


# -- hit rates --------------------------------------------------------------------------

LABEL_WIDTH = 2.6  # inches a configuration's name may take on the hit-rate figure


def hit_rates_figure(rows: list[dict[str, Any]]) -> Figure:
    """Hit rate with its 95% Wilson interval, one row per configuration (its name
    wrapped to fit, and the groups it has no runs in named) and one marker colour and
    shape per group (family and size), in one panel."""
    groups = list(dict.fromkeys(r["group"] for r in rows))
    configs = list(dict.fromkeys(r["config"] for r in rows))
    have = {(r["group"], r["config"]) for r in rows}
    labels = []
    for c in configs:
        label = wrap(c, LABEL_WIDTH)
        missing = [g for g in groups if (g, c) not in have]
        if missing and len(groups) > 1:
            label += "\n" + wrap(f"(no runs: {', '.join(missing)})", LABEL_WIDTH)
        labels.append(label)
    ng = max(len(groups), 1)
    slot = np.array([max(0.3, 0.085 * ng + 0.12, height(lines_of(label)) + 0.08)
                     for label in labels])  # inches per configuration
    centre = np.cumsum(slot) - slot / 2
    step = min(0.085, 0.7 * slot.min() / ng)
    fig, ax = subplots(figsize=(WIDTH, 1.1 + slot.sum()), layout="constrained")
    handles = {}
    for k, (group, colour) in enumerate(zip(groups, colours(len(groups)))):
        rs = {r["config"]: r for r in rows if r["group"] == group}
        there = np.array([c in rs for c in configs])
        if not there.any():
            continue
        rate = np.array([rs[c]["hit_rate"] for c in configs if c in rs], np.float64)
        lo = np.array([rs[c]["hit_rate_ci_low"] for c in configs if c in rs], np.float64)
        hi = np.array([rs[c]["hit_rate_ci_high"] for c in configs if c in rs], np.float64)
        err = 100 * np.maximum(0.0, np.array([rate - lo, hi - rate]))
        y = centre[there] + (k - (len(groups) - 1) / 2) * step
        handles[group] = ax.errorbar(100 * rate, y, xerr=err, fmt=MARKERS[k % len(MARKERS)],
                                     ms=4, capsize=2, color=colour, label=group)
    ax.set_yticks(centre, labels, fontsize=TEXT)
    ax.set_ylim(slot.sum(), 0)
    ax.set_xlim(-3, 103)
    ax.set_xlabel("runs reaching the optimum (%), 95% Wilson interval", fontsize=8)
    ax.tick_params(axis="x", labelsize=TEXT)
    ax.grid(alpha=0.3)
    if len(groups) > 1:
        _legend(fig, handles)
    elif groups:
        ax.set_title(wrap(groups[0], WIDTH - LABEL_WIDTH - 0.5, 8), fontsize=8)
    return fig


def hit_rates(rows: list[dict[str, Any]], path: str) -> str:
    """:func:`hit_rates_figure`, saved to ``path`` (PNG, and a PDF beside it)."""
    return save(hit_rates_figure(rows), path)


# -- ECDFs ------------------------------------------------------------------------------

def gap_ecdf_figure(table: pd.DataFrame, configs: list[str]) -> Figure:
    """ECDF of the final gaps, one panel per group (shared axes, one legend); gaps below
    the axis's left end (hits among them) are counted there, infeasible runs never."""
    group, config = table["group"].to_numpy(), table["config"].to_numpy()
    groups = list(dict.fromkeys(group.tolist()))
    fig, axes = panels(len(groups))
    gap = 100 * numeric(table, "gap")
    grid = np.logspace(np.log10(100 * GAP_FLOOR), 2, 300)  # 0.01% to 100%
    drawn = Drawn(styles(configs))
    for ax, g in zip(axes, groups):
        curves = {}
        for c in configs:
            m = (group == g) & (config == c)
            if m.any():
                curves[c] = (grid, stats.ecdf(np.maximum(gap[m], grid[0]), grid))
        drawn.draw(ax, g, curves, step=True)
        _style(ax, g, "final gap to the optimum (%)")
    return _finish(fig, axes, drawn.handles(configs), "fraction of runs within",
                   "Final gaps (left end: gap under 0.01%, hits included; infeasible runs "
                   "never count)", drawn.note())


def gap_ecdf(table: pd.DataFrame, configs: list[str], path: str) -> str:
    """:func:`gap_ecdf_figure`, saved to ``path`` (PNG, and a PDF beside it)."""
    return save(gap_ecdf_figure(table, configs), path)


HINDSIGHT = ("known only in hindsight: a run cannot tell it has come within a target until "
             "it ends and its path is compared with the exact optimum")


def evaluations_ecdf_figure(table: pd.DataFrame, configs: list[str]) -> Figure:
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
                        "evaluations", True,
                        f"Evaluations until a run's best first came within the target "
                        f"({HINDSIGHT}); solvers that count no evaluations are left out")


def evaluations_ecdf(table: pd.DataFrame, configs: list[str], path: str) -> str:
    """:func:`evaluations_ecdf_figure`, saved to ``path`` (PNG, and a PDF beside it)."""
    return save(evaluations_ecdf_figure(table, configs), path)


def _ecdf_panels(table: pd.DataFrame, configs: list[str], targets, grid, xlabel: str,
                 xlog: bool, title: str = "", refs: dict[str, np.ndarray] | None = None
                 ) -> Figure:
    """ECDFs of per-run values (``targets``: (values, title) per column of panels) for
    each configuration; one row of panels per group, shared axes, one legend.
    ``refs``: configurations drawn instead as a vertical line in every panel of a
    group, at the median of their values there (label: :func:`_reference`)."""
    group, config = table["group"].to_numpy(), table["config"].to_numpy()
    groups = list(dict.fromkeys(group.tolist()))
    fig, axes = subplots(len(groups), len(targets), figsize=(WIDTH, 1.2 + 2.5 * len(groups)),
                         sharex=True, sharey=True, squeeze=False, layout="constrained")
    refs = refs or {}
    lines = styles(configs)
    drawn = Drawn(lines)
    for i, (row, g) in enumerate(zip(axes, groups)):
        for ax, (values, name) in zip(row, targets):
            curves = {}
            for c in configs:
                m = (group == g) & (config == c)
                if m.any() and c not in refs:
                    curves[c] = (grid, stats.ecdf(values[m], grid))
            drawn.draw(ax, f"{g}: {name}", curves, step=True)
            for c, secs in refs.items():
                m = (group == g) & (config == c) & np.isfinite(secs)
                if m.any():
                    _reference(ax, c, float(np.median(secs[m])), lines[c], grid)
            _style(ax, f"{g}: {name}", xlabel if i == len(groups) - 1 else "", xlog)
        row[0].set_ylabel("fraction of runs", fontsize=8)
    handles = drawn.handles(configs)
    for c in refs:
        if c in lines:
            handles[f"{c}: its median seconds to its answer (vertical line)"] = Line2D(
                [], [], color=lines[c]["color"], ls=(0, (5, 2)), lw=1.4)
    return _finish(fig, [], handles, "", title, drawn.note())


def _seconds(t: float) -> str:
    return f"{1000 * t:.3g} ms" if t < 1 else f"{t:.3g} s"


def _reference(ax, config: str, at: float, style: dict[str, Any], grid) -> None:
    """A vertical line at ``at`` in the configuration's colour, with its time beside it."""
    ax.axvline(at, color=style["color"], ls=(0, (5, 2)), lw=1.4, gid=config,
               label=f"{config} (median)")
    lo, hi = np.log10(grid[0]), np.log10(grid[-1])
    right = (np.log10(at) - lo) / max(hi - lo, 1e-12) < 0.2  # near the left edge: beside it
    ax.text(at, 0.5, f" exact: {_seconds(at)} ", rotation=90, fontsize=6, color=style["color"],
            ha="left" if right else "right", va="center",
            transform=blended_transform_factory(ax.transData, ax.transAxes),
            path_effects=[patheffects.withStroke(linewidth=2, foreground="white")])


def time_to_target_figure(table: pd.DataFrame, configs: list[str]) -> Figure:
    """ECDF of the seconds a run needs to come within 1% of the optimum and to hit it
    (one core, log axis); one row of panels per group, shared axes. A run's time to a
    target is known only in hindsight (the figure says so); the exact solver (solver
    ``"exact"`` in the table) is a vertical line at its median time to its answer, which
    the title explains only where the study has one."""
    secs = [(numeric(table, name) if name in table else np.full(len(table), np.inf), title)
            for name, title in (("time_1pct", "within 1% of the optimum"),
                                ("time_hit", "the optimum (gap < 1e-6)"))]
    finite = np.concatenate([v[np.isfinite(v)] for v, _ in secs] + [np.ones(1)])
    grid = np.logspace(np.log10(max(finite.min(), 1e-6)) - 0.2,
                       np.log10(finite.max()) + 0.2, 300)
    config = table["config"].to_numpy()
    solver = (table["solver"].to_numpy(object) if "solver" in table
              else np.full(len(table), "hga", object))
    answer = numeric(table, "time_s") if "time_s" in table else secs[1][0]
    refs = {c: np.where(config == c, answer, np.inf) for c in configs
            if np.any((config == c) & (solver == "exact"))}
    title = ("Seconds of one run (one core) until the run's best first came within the "
             f"target, {HINDSIGHT}")
    if any(np.isfinite(v).any() for v in refs.values()):  # a line is drawn: say what it is
        title += (". Dashed vertical line: the exact solver's median time to its answer "
                  "(optimal when it returns)")
    return _ecdf_panels(
        table, configs, secs, grid, "seconds until first within the target (one core)", True,
        title, refs)


def time_to_target(table: pd.DataFrame, configs: list[str], path: str) -> str:
    """:func:`time_to_target_figure`, saved to ``path`` (PNG, and a PDF beside it)."""
    return save(time_to_target_figure(table, configs), path)


# -- curves -----------------------------------------------------------------------------

def convergence_figure(docs: list[dict[str, Any]], configs: list[str]) -> Figure:
    """Median best-so-far penalised length over the optimum against evaluations (log
    axes), median over runs, then over a group's scenes; one panel per group."""
    labels = doc_groups(docs)
    docs = [dict(d, family=g) for d, g in zip(docs, labels)]  # grouped by family and size
    groups = list(dict.fromkeys(labels))
    fig, axes = panels(len(groups))
    drawn = Drawn(styles(configs))
    for ax, group in zip(axes, groups):
        curves = {}
        for c in configs:
            ds = [d for d in docs if d["family"] == group and d["config"] == c]
            if not ds or "best_so_far_gap_m" not in ds[0]["curves"]:
                continue
            vals = [d["curves"]["best_so_far_gap_m"][1] for d in ds]
            # Scenes of one family may run for different generation counts (a budget
            # that grows with the obstacle count): a run's best-so-far stays after its
            # last generation, so shorter curves go on at their last value.
            longest = max(len(v) for v in vals)
            med = np.median([list(v) + [v[-1]] * (longest - len(v)) for v in vals], axis=0)
            pop = ds[0]["settings"]["population"]
            curves[c] = (pop * (np.arange(len(med)) + 1.0), 100 * np.maximum(med, GAP_FLOOR))
        drawn.draw(ax, group, curves)
        ax.set_yscale("log")
        _style(ax, group, "evaluations")
    return _finish(fig, axes, drawn.handles(configs),
                   "best so far, % over the optimum", "Convergence: penalised length of the "
                   "best so far (median over runs, then scenes; the floor 1e-4 % is the "
                   "optimum)", drawn.note())


def convergence(docs: list[dict[str, Any]], configs: list[str], path: str) -> str:
    """:func:`convergence_figure`, saved to ``path`` (PNG, and a PDF beside it)."""
    return save(convergence_figure(docs, configs), path)


def anytime_figure(docs: list[dict[str, Any]], configs: list[str]) -> Figure:
    """Gap against seconds of a run (one core, log axis), median and quartiles over
    runs, then the median over a family's scenes; one panel per family, shared axes."""
    labels = doc_groups(docs)
    docs = [dict(d, family=g) for d, g in zip(docs, labels)]  # grouped by family and size
    groups = list(dict.fromkeys(labels))
    fig, axes = panels(len(groups))
    lines = styles(configs)
    handles: dict[str, Any] = {}
    lowest, times = 0.0, []
    drawn = Drawn(lines)
    stars: set[str] = set()
    for ax, group in zip(axes, groups):
        curves = {}
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
                ax.plot([end], [0.0], "*", color=lines[c]["color"], ms=9, label=c, gid=c)
                times.append(end)
                stars.add(c)
                continue
            ax.fill_between(GRID, q[0], q[2], color=lines[c]["color"], alpha=0.15, lw=0)
            curves[c] = (GRID, q[1])
        drawn.draw(ax, group, curves)
        ax.axhline(0, color="0.4", lw=0.6, ls=":")
        ax.set_yscale("symlog", linthresh=0.1)
        _style(ax, group, "seconds of one run (one core)")
    for c in configs:
        if c in drawn.where:
            handles[c] = proxy(lines[c])
        elif c in stars:
            handles[c] = Line2D([], [], ls="none", marker="*", color=lines[c]["color"], ms=9)
    ax = axes[0]
    ax.set_ylim(bottom=min(-0.02, 1.5 * lowest))
    ax.set_xlim(*((min(times) / 1.5, max(times) * 1.5) if times else (1e-4, 1.0)))
    return _finish(fig, axes, handles, "gap to the optimum (%)", "Gap held after t seconds: "
                   "median and quartiles over runs, median over scenes\n(above the plot: no "
                   "feasible path yet; below 0: shorter than the optimum)",
                   drawn.note())


def anytime(docs: list[dict[str, Any]], configs: list[str], path: str) -> str:
    """:func:`anytime_figure`, saved to ``path`` (PNG, and a PDF beside it)."""
    return save(anytime_figure(docs, configs), path)


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
