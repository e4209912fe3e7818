"""Study figures that hide nothing, in the cases a user meets: long configuration names,
thirty configurations, curves that coincide, hit rates of 0 % and 100 %, one group or
six, a configuration missing from a group. Each figure is checked as it is written
(``_figure_checks``), at the dpi of its PNG: no text leaves the canvas, no legend
covers data, no two texts overlap, every configuration's curve can be seen.
"""
from __future__ import annotations

import inspect
import zlib
from functools import lru_cache
from unittest import mock

import numpy as np
import pytest
from matplotlib.container import ErrorbarContainer
from matplotlib.lines import Line2D

import _figure_checks as checks
from hga_jax.host.plots import save_figure
from hga_jax.study import figure_lines, figures, stats, table
from hga_jax.study.anytime import GRID

SAVED_DPI = inspect.signature(save_figure).parameters["dpi"].default  # the PNG's
LONG = "random search, 2550 evaluations, population 50 and 0 generations (seeded)"
EXACT = "exact solver"
BEST = "HGA recommended, batched"  # hits in every run: its gap ECDF is the exact solver's
PAPER = "HGA paper, batched"
COPY = "HGA paper, batched again, the same runs under a second and much longer name"
GROUPS6 = ["clutter9", "obstructed9", "obstructed, 15 obstacles", "obstructed, 25 obstacles",
           "robocup_paper", "obstructed9_held"]
PEERS = [(PAPER, "hga", 0.3, 1.0), (BEST, "hga", 1.0, 0.8),
         ("HGA paper, one run at a time", "hga", 0.3, 3.0), (LONG, "random", 0.0, 2.0),
         ("DEAP GA (paper)", "deap", 0.05, 50.0), (EXACT, "exact", 1.0, 1.2)]


# -- synthetic studies ------------------------------------------------------------------

def _rng(*key) -> np.random.Generator:
    return np.random.default_rng(zlib.crc32(repr(key).encode()))


def _doc(config: str, solver: str, group: str, scene: int, hit: float, speed: float,
         runs: int = 12, population: int = 50, generations: int = 50) -> dict:
    """A cell document as :mod:`hga_jax.study.store` and :mod:`hga_jax.study.solvers`
    write it: ``hit`` is the chance a run reaches the optimum (the exact solver: one
    run, gap 0), ``speed`` scales its seconds. ``group``: a family's name, or
    ``"<family>, <n> obstacles"`` (give two sizes of that family), or
    ``"robocup_paper"`` (a scene file of the study)."""
    rng = _rng(config, group, scene)
    exact = solver == "exact"
    n = 1 if exact else runs
    counted = solver in ("hga", "random", "deap")  # evaluations counted
    if exact or hit >= 1.0:
        gap = np.zeros(n)
    else:
        gap = np.where(rng.random(n) < hit, 0.0, np.exp(rng.normal(-3.0, 1.2, n)))
        gap[rng.random(n) < 0.1] = np.inf  # an infeasible run now and then
    time_s = 1e-3 * speed * (np.ones(n) if exact else np.exp(rng.normal(0.0, 0.3, n)))
    gens = generations + 1
    cols = {"run": list(range(n)), "length": [10.0 * (1 + g) for g in gap],
            "feasible": [bool(np.isfinite(g)) for g in gap],
            "violations": [0 if np.isfinite(g) else 1 for g in gap],
            "violations_full": [0 if np.isfinite(g) else 1 for g in gap],
            "gap": [float(g) if np.isfinite(g) else None for g in gap],
            "hit": [bool(g < 1e-6) for g in gap],
            "generation_best": [gens - 1 if counted else None] * n}
    for tag, target in (("hit", 0.0), ("1pct", 0.01), ("5pct", 0.05)):
        reached = gap <= target + 1e-9
        gen = np.minimum(gens - 1, rng.integers(3, gens, n))
        cols[f"generation_{tag}"] = [int(g) if r and counted else None
                                     for g, r in zip(gen, reached)]
        cols[f"evaluations_{tag}"] = [population * (int(g) + 1) if r and counted else None
                                      for g, r in zip(gen, reached)]
        cols[f"time_{tag}"] = [float(t if exact else t * (g + 1) / gens) if r else None
                               for g, r, t in zip(gen, reached, time_s)]
    cols["evaluations_run"] = [population * gens if counted else None] * n
    cols["time_s"] = time_s.tolist()
    final = float(np.median(np.where(np.isfinite(gap), gap, 1.0)))
    curves: dict = {}
    if counted:  # best so far over the optimum, quartiles over runs, per generation
        med = final + 0.4 * np.exp(-np.arange(gens) / (6 + 30 * (1 - hit)))
        curves["best_so_far_gap_m"] = [list(med * 1.3), list(med), list(med * 0.8)]
    if exact:
        q = np.where(GRID >= time_s[0], 0.0, np.inf)
    else:  # the gap held after each time, falling until the run's end
        ends = np.logspace(np.log10(time_s.min() / gens), np.log10(time_s.max()), 12)
        q = np.min([np.where(GRID >= e, final + 0.3 * np.exp(-k / 3), np.inf)
                    for k, e in enumerate(ends)], axis=0)
    curves["anytime_gap"] = [list(q * 1.5), list(q), list(q * 0.5)]
    family, _, size = group.partition(", ")
    files = group == "robocup_paper"
    return {"solver": solver, "batch": True, "config": config,
            "settings": {"population": population, "generations": generations},
            "scenario": group if files else f"{group}_{scene}",
            "family": "files" if files else family,
            "obstacles": int(size.split()[0]) if size else 9, "seed": 0, "runs": n,
            "optimum": 10.0, "evaluations_per_run": population * gens if counted else None,
            "search_s": float(time_s.sum()), "compile_s": 0.0, "columns": cols,
            "curves": curves}


def study(configs: list[tuple[str, str, float, float]], groups: list[str], scenes: int = 3,
          missing: tuple[str, str] | None = None, copies: dict[str, str] | None = None):
    """``(table, docs, labels)`` of a synthetic study: ``configs`` as (label, solver,
    chance of a hit, time scale); ``missing``: a (configuration, group) with no cells;
    ``copies``: configurations (label: the label of another) whose runs are another's."""
    docs = [_doc(c, solver, g, k, hit, speed)
            for g in groups for k in range(scenes) for c, solver, hit, speed in configs
            if (c, g) != missing]
    labels = [c for c, *_ in configs]
    for copy, of in (copies or {}).items():
        docs += [dict(d, config=copy) for d in docs if d["config"] == of]
        labels.append(copy)
    tab = table.build("s", docs)
    assert list(dict.fromkeys(tab["group"])) == groups
    return tab, docs, labels


def hit_rows(configs: list[tuple[str, float]], groups: list[str], runs: int = 300,
             missing: tuple[str, str] | None = None) -> list[dict]:
    """Summary rows (as :func:`hga_jax.study.summary.summarize` makes them) with the given
    hit rates and their Wilson intervals."""
    rows = []
    for g in groups:
        for c, rate in configs:
            if (c, g) == missing:
                continue
            k = round(rate * runs)
            lo, hi = stats.wilson(k, runs)
            rows.append({"group": g, "config": c, "solver": "hga", "runs": runs,
                         "hit_rate": k / runs, "hit_rate_ci_low": lo, "hit_rate_ci_high": hi})
    return rows


def many(n: int = 30) -> list[tuple[str, str, float, float]]:
    """``n`` GA configurations as the operator study has them, every fourth one named
    at length; hit chances from 0 to 1."""
    out = [("paper", "hga", 0.4, 1.0)]
    for i in range(1, n):
        name = (f"perm_crossover=ox1, perm_mutation=exchange, pc_upper=0.{i % 9 + 1}, "
                f"label_binding=obstacle, variant {i}" if i % 4 == 0 else f"elites={i}")
        out.append((name, "hga", (i % 7) / 6, 1.0 + 0.1 * i))
    return out


CASES = {  # (configurations, groups, a configuration missing from a group, copies)
    "long names, one group": (PEERS, ["obstructed9"], None, ()),
    "two groups, one missing, a copy": (PEERS, ["clutter9", "obstructed9"],
                                        (BEST, "clutter9"), ((COPY, PAPER),)),
    "six groups, one missing": (PEERS, GROUPS6, (BEST, "clutter9"), ()),
    "thirty configurations": (many(30), ["clutter9", "obstructed9"], None, ()),
}


@lru_cache(maxsize=None)
def case(name: str):
    """``(table, docs, summary rows, labels)`` of a case of :data:`CASES`."""
    configs, groups, missing, copies = CASES[name]
    tab, docs, labels = study(configs, groups, missing=missing, copies=dict(copies))
    rate = {c: h for c, _, h, _ in configs}
    rate.update({copy: rate[of] for copy, of in copies})
    rows = hit_rows(list(rate.items()), groups, missing=missing)
    return tab, docs, rows, labels


# -- figures as written -----------------------------------------------------------------

def written(name: str, *args):
    """The figure that ``figures.<name>(*args, path)`` saves, written as its PNG is (nothing
    is saved), at the PNG's dpi: text widths differ from one dpi to another."""
    out = []
    with mock.patch.object(figures, "save", lambda fig, path: out.append(fig) or path):
        getattr(figures, name)(*args, "unused.png")
    fig = checks.rendered(out[0])
    fig.set_dpi(SAVED_DPI)
    return fig


@lru_cache(maxsize=None)
def drawn(kind: str, name: str):
    """:func:`written` figure ``kind`` of case ``name`` (drawn once, checked by several tests)."""
    return written(kind, *args_of(kind, *case(name)))


def args_of(kind: str, tab, docs, rows, labels):
    return {"hit_rates": (rows,), "anytime": (docs, labels),
            "convergence": (docs, labels)}.get(kind, (tab, labels))


KINDS = ["hit_rates", "gap_ecdf", "evaluations_ecdf", "time_to_target", "anytime",
         "convergence"]


def all_text(fig) -> str:
    return "\n".join(t.get_text() for t in checks.texts(fig))


def lines_of(ax, label: str) -> list[Line2D]:
    return [a for a in ax.get_lines() if a.get_label() == label]


def legend_labels(fig) -> list[str]:
    return [t.get_text().replace("\n", " ") for leg in fig.legends for t in leg.get_texts()]


ROWS = ("evaluations_ecdf", "time_to_target")  # a row of panels per group
LAYOUTS = [pytest.param(kind, name, marks=pytest.mark.slow)
           # six rows of panels: the same rules as two rows (thirty configurations)
           if kind in ROWS and name.startswith("six") else (kind, name)
           for kind in KINDS for name in CASES]


@pytest.mark.parametrize("kind, name", LAYOUTS)
def test_every_figure_keeps_its_texts_on_the_page_and_apart(kind, name):
    """Long names, thirty configurations, six groups with one configuration missing, two
    configurations with the same runs: no text off the canvas, no legend over data, no
    two texts (tick labels among them) over each other; every configuration is named,
    whole, and styled apart from the others."""
    tab, docs, rows, labels = case(name)
    fig = drawn(kind, name)
    assert checks.texts_off_canvas(fig) == []
    assert checks.legend_over_data(fig) == []
    assert checks.overlapping_texts(fig) == []
    if kind == "hit_rates":
        named = [t.get_text().replace("\n", " ") for t in fig.axes[0].get_yticklabels()]
        assert all(any(n.startswith(c) for n in named) for c in labels)
        return
    named = legend_labels(fig)
    shown = [c for c in labels if c in named]
    assert LONG in named or LONG not in labels  # whole, wrapped onto lines
    assert len(shown) >= len(labels) - 2  # the exact solver and random search: no evaluations
    handles = {t.get_text().replace("\n", " "): h for leg in fig.legends
               for t, h in zip(leg.get_texts(), leg.legend_handles)}
    styles = [(tuple(np.round(handles[c].get_color(), 3)), str(handles[c].get_linestyle()),
               handles[c].get_marker()) for c in shown]
    assert len(set(styles)) == len(styles)
    assert len({s[2] for s in styles}) > 1 or len(styles) == 1  # markers tell apart too


def test_hit_rates_fit_a_long_name_and_name_groups_without_runs():
    """A 70-character name stays whole on the page; 0 % and 100 % show with their
    intervals; a configuration missing from a group says so; groups differ in marker."""
    configs = [("none", 0.0), ("all", 1.0), (LONG, 0.5), (BEST, 1.0)]
    rows = hit_rows(configs, GROUPS6, missing=(BEST, "clutter9"))
    fig = written("hit_rates", rows)
    assert checks.problems(fig) == []
    assert checks.overlapping_texts(fig) == []
    ax = fig.axes[0]
    ticks = {t.get_text().replace("\n", " "): t for t in ax.get_yticklabels()}
    assert any(t.startswith(LONG) for t in ticks)
    assert any(t.startswith(BEST) and "no runs" in t and "clutter9" in t for t in ticks)
    lo, hi = ax.get_xlim()
    bars = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
    assert len(bars) == len(GROUPS6)
    for bar in bars:
        x = bar.lines[0].get_xdata()
        assert {0.0, 100.0} <= set(np.round(x, 9)) and lo < x.min() and x.max() < hi
        for caps in bar.lines[1]:  # the interval's ends lie inside the axes too
            assert lo < caps.get_xdata().min() and caps.get_xdata().max() < hi
    assert len({bar.lines[0].get_marker() for bar in bars}) == len(GROUPS6)


CURVES = ["gap_ecdf", "evaluations_ecdf", "time_to_target", "anytime", "convergence"]


@pytest.mark.parametrize("kind", CURVES)
def test_curves_that_coincide_each_show_and_are_named(kind):
    """Two configurations with the same runs (and, in the gap ECDF, the recommended HGA
    and the exact solver, which both hit in every run): the curve drawn first is not
    hidden (it is wider than the one on top, or shows markers where that one has none),
    and a note in the figure names both."""
    fig = drawn(kind, "two groups, one missing, a copy")
    pairs = [(PAPER, COPY)] + ([(BEST, EXACT)] if kind == "gap_ecdf" else [])
    for under, over in pairs:
        seen = 0
        for ax in fig.axes:
            a, b = lines_of(ax, under), lines_of(ax, over)
            if not (a and b):
                continue
            a, b = a[0], b[0]
            assert np.array_equal(a.get_xydata(), b.get_xydata(), equal_nan=True)
            seen += 1
            kids = ax.get_children()
            if kids.index(a) > kids.index(b) or a.get_zorder() > b.get_zorder():
                a, b = b, a  # a: the one drawn first, underneath
            wider = a.get_linewidth() > b.get_linewidth() + 0.5
            marked = (a.get_marker() not in ("None", "", " ", None)
                      and (a.get_marker() != b.get_marker()
                           or a.get_markevery() != b.get_markevery()))
            assert wider or marked, (ax.get_title(), under, over)
        assert seen, (under, over)
        text = all_text(fig).replace("\n", " ")
        assert "coincide" in text and f"\u201c{under}\u201d" in text
        assert f"\u201c{over}\u201d" in text


def test_time_ecdf_says_what_the_time_means_and_draws_the_exact_solver_as_a_line():
    """The time to a target is known only in hindsight, and the figure says so; the exact
    solver is no ECDF among the runs but a vertical line per panel at its median time,
    named in the legend."""
    tab, docs, rows, labels = case("two groups, one missing, a copy")
    fig = drawn("time_to_target", "two groups, one missing, a copy")
    assert "hindsight" in all_text(fig)
    assert any(EXACT in label and "median" in label for label in legend_labels(fig))
    groups = list(dict.fromkeys(tab["group"]))
    panels = [ax for ax in fig.axes if ax.get_visible()]
    assert len(panels) == 2 * len(groups)
    for k, ax in enumerate(panels):
        g = groups[k // 2]
        mine = tab[(tab["group"] == g) & (tab["config"] == EXACT)]
        want = float(np.median(mine["time_s"]))
        refs = [a for a in ax.get_lines() if a.get_gid() == EXACT or a.get_label() == EXACT]
        assert len(refs) == 1, ax.get_title()
        x = np.asarray(refs[0].get_xdata(), np.float64)
        assert np.all(x == x[0]) and x[0] == pytest.approx(want, rel=1e-12), ax.get_title()
        assert refs[0].get_drawstyle() == "default"  # no steps: a vertical line


def test_a_curve_with_no_finite_point_is_drawn_without_markers():
    """A configuration whose curve has no finite point (no run had a feasible path by
    then) is still a legend entry; markers spaced along a line need a point to start at."""
    fig, ax = figures.subplots()
    styles = figure_lines.styles(["none", "some"])
    x = np.array([1.0, 2.0, 3.0])
    figure_lines.draw(ax, {"none": (x, np.full(3, np.nan)), "some": (x, np.array([3.0, 2.0, 1.0]))},
                  styles)
    fig.canvas.draw()  # would raise where markers are asked of an empty line
    (none,), (some,) = lines_of(ax, "none"), lines_of(ax, "some")
    assert none.get_marker() in ("", "None", None) and some.get_marker() == styles["some"]["marker"]
