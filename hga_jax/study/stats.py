"""Statistics of a study, from scipy: intervals, tests, anytime measures.

- Hit rate: 95 % Wilson score interval (``scipy.stats.binomtest``).
- Median gap: 95 % percentile bootstrap interval (``scipy.stats.bootstrap``, 2,000
  resamples, fixed seed); an infeasible run's gap counts as infinite.
- Each configuration against the reference (the study's first configuration), on
  the same scenes: two-sided Mann-Whitney U on gaps (``scipy.stats.mannwhitneyu``)
  and two-sided Fisher's exact test on hit counts (``scipy.stats.fisher_exact``);
  Holm's step-down correction over every comparison of a table, per test.
- Anytime (the COCO / IOHprofiler way): for a target gap, a run's evaluations to
  reach it (infinite if never); their empirical distribution, and the expected
  running time ``ERT = (evaluations spent by all runs until they reached the
  target or ran out) / (runs that reached it)``.
"""
from __future__ import annotations

import numpy as np
from scipy import stats

BOOTSTRAP_RESAMPLES = 2000
BIG = 1e300  # stands for an infinite gap in rank tests


def wilson(hits: int, runs: int) -> tuple[float, float]:
    """95 % Wilson score interval of a proportion ``hits / runs``."""
    ci = stats.binomtest(int(hits), int(runs)).proportion_ci(0.95, method="wilson")
    return float(ci.low), float(ci.high)


def median_ci(values: np.ndarray, seed: int = 0) -> tuple[float, float, float]:
    """``(median, low, high)``: the median and its 95 % percentile bootstrap interval."""
    x = np.asarray(values, np.float64)
    med = float(np.median(x))
    if len(x) < 2 or np.all(x == x[0]):
        return med, med, med
    with np.errstate(invalid="ignore"):  # its standard error is nan with infinite gaps
        res = stats.bootstrap((x,), np.median, n_resamples=BOOTSTRAP_RESAMPLES, batch=100,
                              method="percentile", random_state=np.random.default_rng(seed))
    ci = res.confidence_interval
    return med, float(ci.low), float(ci.high)


def mann_whitney(a: np.ndarray, b: np.ndarray) -> float:
    """Two-sided Mann-Whitney U p-value (infinite gaps rank last, tied)."""
    a, b = np.minimum(a, BIG), np.minimum(b, BIG)
    if np.all(a == a[0]) and np.array_equal(np.unique(a), np.unique(b)):
        return 1.0
    return float(stats.mannwhitneyu(a, b, alternative="two-sided").pvalue)


def fisher(hits_a: int, runs_a: int, hits_b: int, runs_b: int) -> float:
    """Two-sided Fisher's exact test p-value on a 2x2 table of hits and misses."""
    table = [[hits_a, runs_a - hits_a], [hits_b, runs_b - hits_b]]
    return float(stats.fisher_exact(table, alternative="two-sided").pvalue)


def holm(pvalues) -> np.ndarray:
    """Holm's step-down adjusted p-values (same order as given; nan stays nan)."""
    p = np.asarray(pvalues, np.float64)
    out = np.full(p.shape, np.nan)
    ok = np.flatnonzero(~np.isnan(p))
    order = ok[np.argsort(p[ok], kind="stable")]
    m = len(order)
    adj = np.maximum.accumulate((m - np.arange(m)) * p[order]) if m else p[order]
    out[order] = np.minimum(adj, 1.0)
    return out


def ert(evaluations: np.ndarray, budget: np.ndarray) -> float:
    """Expected running time (evaluations) to a target; inf when no run reached it.

    ``evaluations``: per run, evaluations to the target (inf: never);
    ``budget``: per run, the evaluations it spent in all.
    """
    e = np.asarray(evaluations, np.float64)
    reached = np.isfinite(e)
    if not reached.any():
        return float("inf")
    spent = np.where(reached, e, np.asarray(budget, np.float64))
    return float(spent.sum() / reached.sum())


def ecdf(values: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Fraction of ``values`` at most each grid point (inf never counts)."""
    v = np.sort(np.asarray(values, np.float64))
    return np.searchsorted(v, grid, side="right") / max(len(v), 1)
