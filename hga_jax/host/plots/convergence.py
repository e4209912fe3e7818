"""GA convergence over generations (the paper's Fig. 5 and more): best and mean
fitness, the best-so-far length against the optimum, and the share of runs that got
within 1 % and to the optimum by each number of evaluations."""
from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from .style import C_ARC, C_LINE, EDGE_PAD_PT

C_SO_FAR = "tab:purple"  # the best so far, in both panels
OPT_Z = 1.5  # the optimum's line lies under the curves (lines 2, 2.5) and over the bands (1)
MIN_LENGTH_SPAN = 0.01  # the length panel's range: at least this share of the length
MIN_SHARE_SPAN = 10.0  # the share panel's y axis shows at least 0..10 %


def _per_generation(values: Any) -> np.ndarray:
    """``values`` as a (G+1, runs) array (a 1-D array is one run); G+1 may be 0."""
    a = np.asarray(values, float)
    if a.size == 0:
        return np.zeros((len(a), a.shape[1] if a.ndim > 1 else 1))
    return a.reshape(len(a), -1)


def _band(ax: Axes, gens: np.ndarray, data: np.ndarray, colour: str, label: str, gid: str,
          zorder: float = 2.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Median over runs (line) and interquartile band of a (G+1, runs) array;
    returns the quartiles and the median."""
    if data.size:
        q1, med, q3 = np.percentile(data, [25, 50, 75], axis=1)
    else:  # no generations or no runs: nothing to draw
        q1 = med = q3 = np.full(len(gens), np.nan)
    ax.fill_between(gens, q1, q3, color=colour, alpha=0.22, lw=0, gid=gid + "_band")
    ax.plot(gens, med, color=colour, lw=1.8, label=label, gid=gid + "_median", zorder=zorder,
            marker="o" if len(gens) == 1 else None, ms=4)  # one generation: a point
    return q1, med, q3


def restarts_of(best_fitness: Any, restart_after: int) -> np.ndarray:
    """Per generation and run (a (G+1, runs) bool array) whether the run started a new
    population there: the GA's rule (:mod:`hga_jax.search.settings`, ``restart_after =
    R``), read from the best fitness of each generation. The best so far is the running
    maximum of those; at a generation ``g = R, 2R, ...`` a run restarts when its best so
    far last improved at generation ``g - R`` or before. ``restart_after`` 0: none."""
    best = _per_generation(best_fitness)
    out = np.zeros(best.shape, bool)
    r = int(restart_after or 0)
    if r <= 0 or best.shape[0] <= r:
        return out
    so_far = np.maximum.accumulate(best, axis=0)
    gens = np.arange(best.shape[0])[:, None]
    better = np.r_[np.ones((1, best.shape[1]), bool), so_far[1:] > so_far[:-1]]
    last = np.maximum.accumulate(np.where(better, gens, 0), axis=0)  # last improvement
    g = gens[r::r]  # the generations where a stalled run may restart
    out[r::r] = last[g[:, 0] - 1] <= g - r
    return out


def headroom(ax: Any, y: float, share: float = 0.08) -> None:
    """Keep a horizontal line at ``y`` off the frame: widen the y range to leave
    ``share`` of it on the far side of ``y``."""
    lo, hi = ax.get_ylim()
    span = (hi - lo) or abs(y) or 1.0
    if y >= hi - 0.02 * span:
        ax.set_ylim(lo, y + share * span)
    if y <= lo + 0.02 * span:
        ax.set_ylim(y - share * span, ax.get_ylim()[1])


def _optimum_line(ax: Axes, y: float, label: str, gid: str) -> None:
    """The optimum as a wide grey line under the curves: a median that reaches the
    optimum runs along its middle and both stay in sight."""
    ax.axhline(y, color="0.55", lw=4.0, alpha=0.6, solid_capstyle="butt", zorder=OPT_Z,
               label=label, gid=gid)


def _legend_above(ax: Axes, ncol: int = 1, title: str | None = None) -> None:
    """The axes' legend above its frame, on no data (the layout makes room), titled
    ``title`` (what the curves and bands are over runs)."""
    ax.legend(fontsize=8, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=ncol,
              frameon=False, borderaxespad=0.3, handlelength=2.2, title=title,
              title_fontsize=8)


def _short(v: float) -> str:
    """A count written short: 500, 2k, 50k, 1M."""
    for size, unit in ((1e6, "M"), (1e3, "k")):
        if abs(v) >= size:
            return f"{v / size:g}{unit}"
    return f"{v:g}"


def _useful_range(q1: np.ndarray, q3: np.ndarray, also: float | None) -> tuple[float, float, int]:
    """The y range that shows the quartiles from the first generations on that matter:
    ``(low, high, g0)``, where generations before ``g0`` may run off the top (``g0`` 0:
    everything fits). A few huge early values (penalised lengths of infeasible paths)
    would otherwise squash the rest into a sliver: the range fits the quartiles from
    generation ``g0`` (a tenth of the way in, at least 1) on, unless the whole range is
    less than four times that (a curve that merely falls fast keeps its start)."""
    ok = np.isfinite(q1) & np.isfinite(q3)
    if not ok.any():
        return (np.nan, np.nan, 0)
    extra = [float(also)] if also is not None and np.isfinite(also) else []
    low, high = min(float(q1[ok].min()), *extra), max(float(q3[ok].max()), *extra)
    g0 = max(1, int(round(0.1 * (len(q3) - 1))))
    late = q3[g0:][np.isfinite(q3[g0:])]
    if len(late) == 0:
        return (low, high, 0)
    top = max(float(late.max()), *extra)
    if top <= low or high - low <= 4.0 * (top - low):
        return (low, high, 0)
    return (low, top, g0)


def plot_convergence(best_fitness: np.ndarray, mean_fitness: np.ndarray, *,
                     optimum_fitness: float | None = None, best_length: np.ndarray | None = None,
                     optimum_length: float | None = None, title: str | None = None,
                     length_label: str = "best path length (m)",
                     reached: dict[str, np.ndarray] | None = None,
                     population: int | None = None, restart_after: int = 0) -> Figure:
    """Fitness over generation (paper Fig. 5) from arrays shaped (G+1, runs).

    Row ``g`` is generation ``g`` (0 = initial population). Draws the median
    over runs and the interquartile band of the best and the mean fitness of the
    current population, the median of the best so far (the running maximum of the
    best), the optimum's fitness as a line when given, the generations where a run
    restarted (``restart_after``: the GA's setting, :func:`restarts_of`) as dotted
    vertical lines, and, when ``best_length`` is given,
    a second panel of the best-so-far path length against the optimum length
    (``length_label`` names its axis). ``reached`` (label -> per run the first
    generation it got there, -1 never) adds a panel of the share of runs there by
    each number of evaluations (``population`` per generation), on a log axis (when
    they span a decade or more): it still tells a story when every run finds the
    optimum in generation 0.

    Legends sit above their panels, clear of the data (the best and the mean of the
    current population fall at each restart of a stalled run; the best so far does
    not). The optimum is a wide grey line under the curves, so a median on the optimum
    stays visible and so does the optimum. The length panel's
    range fits the quartiles after the first generations when a few huge early values
    (penalised lengths) would squash them; its label says so. The share panel's range
    ends a little above the highest share (at least 10 %), so a low hit rate shows.
    """
    best, mean = _per_generation(best_fitness), _per_generation(mean_fitness)
    runs, gens = best.shape[1], np.arange(best.shape[0])
    what = ("lines: median over %d runs; bands: interquartile range" % runs if runs > 1
            else "1 run")
    count = 1 + (best_length is not None) + (reached is not None)
    fig = Figure(figsize=(3.6 + 3.4 * (count - 1) if count > 1 else 6.0, 4.3),
                 layout="constrained")
    fig.get_layout_engine().set(w_pad=EDGE_PAD_PT / 72, h_pad=EDGE_PAD_PT / 72)
    axes = fig.subplots(1, count, squeeze=False)[0]
    two = best_length is not None
    last = max(len(gens) - 1, 1)
    x0 = -0.1 if len(gens) == 1 else 0  # one generation: its point off the frame
    ax = axes[0]
    _band(ax, gens, best, C_ARC, "best of the current population", "best", zorder=2.5)
    _band(ax, gens, mean, C_LINE, "mean of the current population", "mean")
    if best.size:  # thin and dashed over the population's best, which it equals between restarts
        so_far = np.median(np.maximum.accumulate(best, axis=0), axis=1)
        ax.plot(gens, so_far, color=C_SO_FAR, lw=1.1, ls=(0, (4, 2)), zorder=2.7,
                label="best so far", gid="best_so_far_median",
                marker="o" if len(gens) == 1 else None, ms=3)
    fresh = restarts_of(best, restart_after)
    label = (f"restart (no gain in {restart_after} generations:\na new population; "
             f"{int(fresh.sum())} in all)")
    for g in np.flatnonzero(fresh.any(axis=1)):
        ax.axvline(g, color="0.35", ls=":", lw=0.9, zorder=1.2, gid="restart", label=label)
        label = "_nolegend_"
    if optimum_fitness is not None:
        _optimum_line(ax, float(optimum_fitness), "optimum (grey, under the curves)", "optimum")
        headroom(ax, float(optimum_fitness))
    ax.set_xlabel("generation")
    ax.set_ylabel("fitness  10000 / (Dist$_m$ + 1)")
    ax.set_xlim(x0, last)
    ax.grid(alpha=0.3)
    _legend_above(ax, title=what)
    if two:
        ax2 = axes[1]
        length = _per_generation(best_length)
        q1, _, q3 = _band(ax2, gens, length, C_SO_FAR, "best so far", "length", zorder=2.5)
        label = length_label
        low, high, g0 = _useful_range(q1, q3, optimum_length)
        if optimum_length is not None:
            _optimum_line(ax2, float(optimum_length), "optimum length (grey, under)",
                          "optimum_length")
        if np.isfinite(low) and np.isfinite(high):
            # At least 1% of the length: float32 rounding (1e-7 m) is not drawn as a gap.
            span = max(high - low, MIN_LENGTH_SPAN * abs(high), 1e-9)
            mid = 0.5 * (low + high)
            ax2.set_ylim(mid - 0.55 * span, mid + 0.55 * span)
            ax2.ticklabel_format(axis="y", useOffset=False)
            if g0:
                top = float(np.nanmax(np.where(np.isfinite(q3), q3, np.nan)))
                # on lines of their own: one line would run past the axes' height
                label += f"\n(range fits generations ≥ {g0};\nearlier up to {top:.4g})"
        if optimum_length is not None:
            headroom(ax2, float(optimum_length))
        ax2.set_xlabel("generation")
        ax2.set_ylabel(label)
        ax2.set_xlim(x0, last)
        ax2.grid(alpha=0.3)
        _legend_above(ax2, title=what)
    if reached is not None:
        ax3 = axes[-1]
        pop = population or 1
        evals = pop * (gens + 1)
        highest = 0.0
        styles = ((C_LINE, "-", 3.0), (C_ARC, "--", 1.8), ("tab:green", ":", 1.4))
        for z, ((label, first), (colour, ls, lw)) in enumerate(zip(reached.items(), styles)):
            first = np.asarray(first)
            share = np.array([100 * np.mean((first >= 0) & (first <= g)) if first.size else 0.0
                              for g in gens])
            highest = max(highest, float(share.max()) if share.size else 0.0)
            # Wider lines under narrower ones: curves that coincide all stay in sight.
            ax3.step(evals, share, where="post", color=colour, ls=ls, lw=lw, label=label,
                     gid=f"reached_{label}", zorder=2.0 + 0.1 * z,
                     marker="o" if len(gens) == 1 else None, ms=2 + lw)
        if len(evals) and evals[-1] >= 10 * evals[0]:  # a log axis only over a decade or more
            ax3.set_xscale("log")
            # Labels at 1, 2 and 5 times the powers of ten where the axis spans under 2.5
            # decades (matplotlib's own labels the minor ticks there, which overlap), at
            # the powers alone beyond; written short (500, 1k, 20k, 1M).
            subs = (1.0, 2.0, 5.0) if evals[-1] < 10 ** 2.5 * evals[0] else (1.0,)
            ax3.xaxis.set_major_locator(LogLocator(base=10, subs=subs))
            ax3.xaxis.set_major_formatter(FuncFormatter(lambda v, _: _short(v)))
            ax3.xaxis.set_minor_formatter(NullFormatter())
        top = max(MIN_SHARE_SPAN, 1.15 * highest)  # a bit above the highest share
        ax3.set_ylim(*((-3.0, 103.0) if top >= 100 else (-0.04 * top, top)))
        ax3.set_xlabel(f"evaluations ({pop} per generation)")
        ax3.set_ylabel("runs there (%)")
        ax3.grid(alpha=0.3)
        _legend_above(ax3, ncol=max(1, len(reached)))
    if title is not None:
        fig.suptitle(title, fontsize=9)
    return fig
