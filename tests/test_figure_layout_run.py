"""A run's figures (``path.png``, ``convergence.png``) hide nothing in the cases a user
meets: a long two-line title, a cluttered scene with every obstacle touched, a violation
cross on an obstacle's number, a scene with no obstacles; restarts that make the mean
fitness dip, a median best fitness on the optimum, huge penalised lengths in the first
generations, hit rates of 3.9 % and 100 %, one run, one generation, none. Each figure is
checked as it is written (``_figure_checks``), at the dpi of its PNG.
"""
from __future__ import annotations

import functools
import inspect
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.patches import Circle

import _figure_checks as checks
from _figure_checks import by_gid, legend_labels, written
from hga_jax.host.config import load_scenario
from hga_jax.host.plots import plot_convergence, plot_path, save_figure
from hga_jax.host.report import path_title
from hga_jax.model.path import evaluate_path
from hga_jax.model.scenario import Field, Scenario
from hga_jax.search.settings import GASettings

SAVED_DPI = inspect.signature(save_figure).parameters["dpi"].default  # the PNG's
OPTIMUM_NOTE = "; optimum 2.2454 m (dashed)"  # what ``hga-jax plot --with-optimum`` adds
RHO = r"turning circles ($\rho$)"


def in_axes(ax):
    return lambda t: t.axes is ax and t in ax.texts


# -- scenes and paths ------------------------------------------------------------------

def robocup():
    return load_scenario("configs/scenarios/robocup_paper.toml")


def robocup_violating():
    """Run 1 of the paper's GA on the RoboCup scene (seed 0): 2.2718 m, through robot 6,
    whose number the violation cross lands on."""
    sc = robocup()
    path = evaluate_path(sc, [1, 3, 0, 2, 4, 5, 6, 7, 8], [1, -1, -1, 0, 0, 0, 0, 0, 0, 0, 1])
    assert path.violations_at == [{"kind": "obstacle", "segment": 5, "obstacle": 6}]
    return sc, path


def robocup_optimum(sc):
    path = evaluate_path(sc, [1, 3, 4, 5, 0, 2, 6, 7, 8], [-1, 1, 1, -1, 1, 0, 0, 0, 0, 0, 1])
    assert path.feasible and path.length == pytest.approx(2.2454, abs=1e-4)
    return path


def long_title(path) -> str:
    st = GASettings(selection="roulette", perm_crossover="cx", perm_mutation="inversion")
    return path_title("robocup_paper", "run 1", path.length, path.violations, "full",
                      st) + OPTIMUM_NOTE


def cluttered():
    """The bundled 28-obstacle scene and its optimum (3.8994 m, four obstacles touched)."""
    sc = load_scenario("configs/scenarios/cluttered.toml")
    rest = [i for i in range(sc.n) if i not in (0, 18, 20, 21)]
    path = evaluate_path(sc, [0, 18, 20, 21] + rest, [1, -1, 1, 1, -1] + [0] * len(rest) + [-1])
    assert path.feasible and path.length == pytest.approx(3.8994, abs=1e-4)
    return sc, path


def crowd(n=40, seed=3, gap=0.25, size=(4.0, 3.0)):
    """``n`` robots drawn as cluttered.toml's are (centres at least ``gap`` apart, so
    many model circles of R = 0.18 m overlap their neighbours') in a field of ``size``."""
    rng = np.random.default_rng(seed)
    w, h = size
    centres = []
    while len(centres) < n:
        c = rng.uniform([0.3, 0.3], [w - 0.3, h - 0.3])
        if (all(np.hypot(*(c - d)) >= gap for d in centres)
                and min(np.hypot(*(c - [0.15, 0.2])), np.hypot(*(c - [w - 0.15, h - 0.2]))) > 0.4):
            centres.append(c)
    return Scenario("crowd", 0.09, 0.15, (0.15, 0.2, 0.0), (w - 0.15, h - 0.2, 0.0),
                    np.array(centres), np.full(n, 0.09), Field(0, w, 0, h, True))


def demo():
    """The two-robot scene of test_plots: a straight line through robot 1's centre."""
    return Scenario("demo", 0.09, 0.2, (0.3, 0.5, 0.0), (2.5, 0.5, 0.0),
                    np.array([[1.4, 0.5], [2.0, 1.2]]), np.full(2, 0.09), Field(0, 3, 0, 1.6, True))


@functools.cache
def _path_inputs():
    """The scenes and paths of the path figures, made once, on first use (not while
    the file is collected, in every worker)."""
    sc, bad = robocup_violating()
    cl, cl_path = cluttered()
    d = demo()
    field = load_scenario("configs/scenarios/open_field.toml")
    return SimpleNamespace(sc=sc, bad=bad, opt=robocup_optimum(sc), cl=cl, cl_path=cl_path,
                           many=crowd(), field=field, d=d,
                           through=evaluate_path(d, [0, 1], [-1, 0, 0, 1]),
                           direct=evaluate_path(field, [], [1, -1]))


def path_figures():
    """Every path figure of this file's cases, by name (each drawn when called)."""
    def on(draw):
        return lambda: draw(_path_inputs())

    return {
        "robocup, violation, long title": on(lambda i: plot_path(
            i.sc, i.bad.segments, touched=i.bad.touched, violations_at=i.bad.violations_at,
            optimum=i.opt.segments, title=long_title(i.bad))),
        "robocup, best": on(lambda i: plot_path(
            i.sc, i.opt.segments, touched=i.opt.touched,
            title=path_title("robocup_paper", "best (run 4)", i.opt.length, 0, "full", GASettings()))),
        "robocup, very long title": on(lambda i: plot_path(
            i.sc, i.opt.segments, touched=i.opt.touched,
            title=long_title(i.bad) + "; " + ", ".join(f"setting {k} = {k / 10}" for k in range(12)))),
        "cluttered, optimum": on(lambda i: plot_path(i.cl, i.cl_path.segments, touched=i.cl_path.touched,
                                                     title="cluttered: optimum")),
        "cluttered, all touched": on(lambda i: plot_path(
            i.cl, i.cl_path.segments, touched=[(k + 1, 1 if k % 2 else -1) for k in range(i.cl.n)])),
        "40 robots, all touched": on(lambda i: plot_path(
            i.many, [], touched=[(k + 1, -1 if k % 3 else 1) for k in range(i.many.n)])),
        "demo, cross on the centre": on(lambda i: plot_path(i.d, i.through.segments,
                                                            violations_at=i.through.violations_at)),
        "open field, no path": on(lambda i: plot_path(i.field, [], title="open_field: no path")),
        "open field, a path": on(lambda i: plot_path(
            i.field, i.direct.segments, title="open_field: Dubins")),
    }


PATHS = path_figures()


# -- path.png ----------------------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(PATHS))
def test_path_figure_keeps_texts_on_the_canvas_and_legend_off_data(name):
    fig = written(PATHS[name]())
    assert checks.texts_off_canvas(fig) == []
    assert checks.legend_over_data(fig) == []
    ax = fig.axes[0]
    assert checks.overlapping_texts(fig, within=in_axes(ax)) == []  # numbers and tags
    assert checks.texts_on_markers(fig) == []


@pytest.mark.parametrize("name", sorted(PATHS))
def test_path_legend_keeps_a_margin_to_the_canvas_edge(name):
    fig = written(PATHS[name]())
    assert checks.legend_margin(fig) >= 4.0  # points
    ax = fig.axes[0]
    assert min(checks.edge_margins(fig, ax.title)) >= 4.0 * SAVED_DPI / 72


def test_long_two_line_title_fits_whole_and_reads_as_given():
    """The title of ``hga-jax plot --run 1 --with-optimum``: two lines, the second with
    the GA's settings and the optimum's note, on an equal-aspect scene with the legend
    outside on the right. It stays the caller's text (``get_title``) and fits the page."""
    sc, bad = robocup_violating()
    title = long_title(bad)
    assert "\n" in title and title.split("\n")[1].startswith("roulette, cx/inversion")
    fig = written(plot_path(sc, bad.segments, touched=bad.touched,
                            violations_at=bad.violations_at,
                            optimum=robocup_optimum(sc).segments, title=title))
    ax = fig.axes[0]
    assert ax.get_title() == title
    left, _, right, top = checks.edge_margins(fig, ax.title)
    assert min(left, right, top) >= 0, checks.texts_off_canvas(fig)
    assert checks.texts_off_canvas(fig) == []
    assert ax.title.get_fontsize() >= 7  # shrunk, if at all, to a size still read


def test_violation_cross_leaves_the_obstacle_number_readable():
    """Run 1's path runs through robot 6: the cross marks the path's point closest to its
    centre, where its number is drawn; the number moves off the cross (and the cross
    stays on the path's closest point)."""
    sc, bad = robocup_violating()
    fig = written(plot_path(sc, bad.segments, touched=bad.touched,
                            violations_at=bad.violations_at, title=long_title(bad)))
    ax = fig.axes[0]
    (cross,) = by_gid(ax, "violation_point")
    (six,) = [t for t in ax.texts if t.get_text() == "6"]
    r = checks._renderer(fig)
    (mark,) = checks.marker_boxes(fig, cross)
    box = six.get_window_extent(r)
    assert not box.overlaps(mark), (box, mark)
    assert checks.texts_on_markers(fig) == []
    # Still next to robot 6: within its model circle.
    centre = ax.transData.transform(sc.centres[5])
    scale = (ax.transData.transform([1, 0]) - ax.transData.transform([0, 0]))[0]
    radius = sc.model_radii[5] * scale
    assert np.hypot(*(box.get_points().mean(axis=0) - centre)) < radius


def test_cross_on_the_centre_itself_moves_the_number_off_it_and_off_the_path():
    d = demo()
    through = evaluate_path(d, [0, 1], [-1, 0, 0, 1])
    fig = written(plot_path(d, through.segments, violations_at=through.violations_at))
    ax = fig.axes[0]
    (cross,) = by_gid(ax, "violation_point")
    assert (cross.get_xdata()[0], cross.get_ydata()[0]) == pytest.approx((1.4, 0.5), abs=1e-9)
    (one,) = [t for t in ax.texts if t.get_text() == "1"]
    box = one.get_window_extent(checks._renderer(fig))
    assert not box.overlaps(checks.marker_boxes(fig, cross)[0])
    for piece in by_gid(ax, "violation_piece"):  # the thick red line runs through the centre
        path = piece.get_transform().transform_path(piece.get_path())
        assert not path.intersects_bbox(box, filled=False)


def _tags_meeting_other_circles(fig, sc, touched) -> list[str]:
    """CW/CCW tags whose boxes reach into another obstacle's model circle (its disc:
    the body and the ring that the outline bounds)."""
    ax = fig.axes[0]
    r = checks._renderer(fig)
    tags = by_gid(ax, "touched")
    circles = by_gid(ax, "model_circle")
    assert len(tags) == len(touched) and len(circles) == sc.n
    bad = []
    for k, tag in zip(sorted(touched), tags):
        box = tag.get_window_extent(r)
        for j, circle in enumerate(circles):
            if j == k:
                continue
            assert isinstance(circle, Circle)
            disc = circle.get_transform().transform_path(circle.get_path())
            if disc.intersects_bbox(box, filled=True):
                bad.append(f"tag {tag.get_text()} of obstacle {k + 1} on obstacle {j + 1}'s circle")
    return bad


def _touched_scenes():
    cl, path = cluttered()
    many = crowd()
    return {"cluttered, optimum": (cl, path, [t.obstacle - 1 for t in path.touched]),
            "cluttered, all touched": (cl, path, list(range(cl.n))),
            "40 robots, all touched": (many, None, list(range(many.n)))}


@pytest.mark.parametrize("name", ["cluttered, optimum", "cluttered, all touched",
                                  "40 robots, all touched"])
def test_cw_ccw_tags_clear_other_obstacles_and_texts(name):
    """On a cluttered scene, each tag sits where no other obstacle's model circle and no
    other text is (the place below the obstacle, the only one before, is often inside a
    neighbour's model circle)."""
    sc, path, touched = _touched_scenes()[name]
    fig = written(PATHS[name]())
    ax = fig.axes[0]
    assert _tags_meeting_other_circles(fig, sc, touched) == []
    assert checks.overlapping_texts(fig, within=in_axes(ax)) == []
    # Each tag names a side and stays by its obstacle: its centre within 1.5 R of the
    # obstacle's centre.
    r = checks._renderer(fig)
    scale = (ax.transData.transform([1, 0]) - ax.transData.transform([0, 0]))[0]
    for k, tag in zip(sorted(touched), by_gid(ax, "touched")):
        assert tag.get_text() in ("CW", "CCW")
        at = tag.get_window_extent(r).get_points().mean(axis=0)
        centre = ax.transData.transform(sc.centres[k])
        assert np.hypot(*(at - centre)) < 1.5 * sc.model_radii[k] * scale


def test_scene_without_obstacles_lists_only_what_is_drawn():
    field = load_scenario("configs/scenarios/open_field.toml")
    assert field.n == 0 and not field.field.keep_inside
    ax = written(plot_path(field, [], title="open_field: no path")).axes[0]
    assert legend_labels(ax) == ["start", "goal", RHO, "field"]
    ax = written(plot_path(field, evaluate_path(field, [], [1, -1]).segments)).axes[0]
    assert "obstacle (robot)" not in legend_labels(ax) and "model circle" not in legend_labels(ax)
    assert {"path arc", RHO, "field"} <= set(legend_labels(ax))


def test_legend_names_model_circles_only_when_one_is_drawn_dashed():
    sc, path = cluttered()
    every = [(k + 1, 1) for k in range(sc.n)]
    labels = legend_labels(written(plot_path(sc, path.segments, touched=every)).axes[0])
    assert "model circle" not in labels  # all are drawn as touched
    assert {"obstacle (robot)", "touched (CW/CCW)"} <= set(labels)
    labels = legend_labels(written(plot_path(sc, path.segments, touched=path.touched)).axes[0])
    assert {"obstacle (robot)", "model circle", "touched (CW/CCW)"} <= set(labels)


# -- convergence.png ----------------------------------------------------------------------

def restarts(runs=30, gens=51, seed=1, optimum=3080.0):
    """Histories of a GA that restarts its stalled runs: the best climbs towards the
    optimum, the mean follows, and both fall sharply at each restart (generations 20
    and 35 for most runs)."""
    rng = np.random.default_rng(seed)
    g = np.arange(gens)[:, None]
    since = np.where(g < 20, g, np.where(g < 35, g - 20, g - 35))
    climb = 1 - np.exp(-since / rng.uniform(4, 9, runs))
    best = 1000 + (optimum - 1000) * climb * rng.uniform(0.85, 1.0, runs)
    mean = 500 + 0.6 * (best - 500) * rng.uniform(0.9, 1.0, (gens, runs))
    return best, mean


def reached_at(gens: int, runs: int, hits: int, start: int = 20) -> np.ndarray:
    first = np.full(runs, -1)
    first[:hits] = np.linspace(start, gens - 1, hits).astype(int) if hits else []
    return first


def convergence(**over):
    best, mean = restarts()
    gens, runs = best.shape
    length = 10000 / best - 1
    kw = dict(optimum_fitness=3080.0, best_length=length, optimum_length=2.2454,
              title="robocup_paper: 30 runs, median and quartiles; collision full; roulette, "
                    "cx/inversion",
              reached={"within 1%": reached_at(gens, runs, 3, 15),
                       "optimum": reached_at(gens, runs, 2)},
              population=50, length_label="best-so-far Dist$_m$ = length + penalty (m)")
    kw.update(over)
    return plot_convergence(best, mean, **kw)


def test_restart_dips_stay_clear_of_the_legends():
    fig = written(convergence())
    assert checks.legend_over_data(fig) == []
    assert checks.texts_off_canvas(fig) == []
    assert checks.overlapping_texts(fig) == []


@pytest.mark.parametrize("panel, line, optimum", [(0, "best_median", "optimum"),
                                                  (1, "length_median", "optimum_length")])
def test_median_on_the_optimum_and_the_optimum_both_show(panel, line, optimum):
    """Most runs reach the optimum: the median best fitness (and best-so-far length)
    coincides with the optimum's line. The median is drawn over the optimum's line, which
    is wider, so both are seen; the legend says the optimum is under the curves."""
    best, mean = restarts()
    best = np.minimum(best * 1.3, 3080.0)  # the median reaches the optimum
    fig = written(plot_convergence(best, mean, optimum_fitness=3080.0,
                                   best_length=10000 / best - 1, optimum_length=10000 / 3080 - 1))
    ax = fig.axes[panel]
    med = by_gid(ax, line)[0]
    assert np.sum(np.isclose(med.get_ydata(), by_gid(ax, optimum)[0].get_ydata()[0])) > 20
    (opt,) = by_gid(ax, optimum)
    assert checks.drawn_over(med, opt) and not checks.drawn_over(opt, med)
    assert opt.get_linewidth() > med.get_linewidth()  # it shows on both sides of the median
    assert "under" in opt.get_label()
    assert checks.problems(fig) == []


def test_huge_early_lengths_leave_the_useful_range_readable():
    """Penalised (infeasible) lengths of hundreds of metres in the first generations; then
    the runs' best-so-far lengths settle between 2.25 and 2.6 m. The length axis fits the
    quartiles after the first generations and says so."""
    rng = np.random.default_rng(5)
    gens, runs = 51, 40
    g = np.arange(gens)[:, None]
    length = 2.2454 + (0.05 + 0.35 * np.exp(-g / 12)) * rng.uniform(0.1, 1.0, runs)
    length[:3] += np.where(rng.random((3, runs)) < 0.7, rng.uniform(300, 700, (3, runs)), 0)
    best = 10000 / (length + 1)
    fig = written(plot_convergence(best, best * 0.6, optimum_fitness=10000 / 3.2454,
                                   best_length=length, optimum_length=2.2454))
    ax2 = fig.axes[1]
    lo, hi = ax2.get_ylim()
    q1, med, q3 = np.percentile(length, [25, 50, 75], axis=1)
    assert lo <= 2.2454 < q1[-1] <= med[-1] <= q3[-1] < hi
    assert hi < 2 * q3[5:].max()  # not squashed by the first generations' hundreds of metres
    assert (q3[-1] - 2.2454) / (hi - lo) > 0.05  # the final spread over the optimum shows
    assert np.all(q3[5:] <= hi)  # from generation 5 on the quartiles are all in view
    assert "generations" in ax2.get_ylabel() and "earlier" in ax2.get_ylabel()
    assert checks.problems(fig) == []


def test_lengths_without_outliers_keep_their_whole_range():
    best, mean = restarts()
    length = 10000 / np.maximum.accumulate(best, axis=0) - 1
    fig = written(plot_convergence(best, mean, best_length=length, optimum_length=2.2454))
    lo, hi = fig.axes[1].get_ylim()
    q1, q3 = np.percentile(length, [25, 75], axis=1)
    assert lo <= min(q1.min(), 2.2454) and hi >= q3.max()
    assert "earlier" not in fig.axes[1].get_ylabel()


def test_every_run_on_the_optimum_draws_no_rounding_as_a_gap():
    """Every run holds the optimum from generation 0; float32 lengths differ from the
    float64 optimum by 2e-7 m. The length panel shows them on one level (a range of at
    least 1% of the length, no offset label over the legend), not 2e-7 m apart."""
    gens, runs, optimum = 51, 200, 2.2454305
    length = np.full((gens, runs), 2.2454307)
    best = 10000 / (length + 1)
    fig = written(plot_convergence(best, best * 0.7, optimum_fitness=10000 / (optimum + 1),
                                   best_length=length, optimum_length=optimum))
    ax2 = fig.axes[1]
    lo, hi = ax2.get_ylim()
    assert hi - lo >= 0.01 * optimum and lo < optimum < 2.2454307 < hi
    assert ax2.yaxis.get_offset_text().get_text() == ""
    assert checks.problems(fig) == []


@pytest.mark.parametrize("hits, runs, top", [(2, 51, 20.0), (0, 30, 20.0), (51, 51, None)])
def test_hit_rate_axis_fits_the_curve(hits, runs, top):
    """A hit rate that ends at 3.9 % (2 of 51 runs) gets an axis up to a bit above it (not
    0-100 %, where it looks flat); none at all still shows 0; 100 % stays in view."""
    best, mean = restarts(runs=runs)
    gens = best.shape[0]
    fig = written(plot_convergence(best, mean, optimum_fitness=3080.0, population=50,
                                   reached={"within 1%": reached_at(gens, runs, hits, 10),
                                            "optimum": reached_at(gens, runs, hits)}))
    ax = fig.axes[-1]
    lo, hi = ax.get_ylim()
    final = 100 * hits / runs
    assert lo < 0 < hi and final < hi
    if top is not None:
        assert hi <= top
    else:
        assert hi > 100
    if hits:  # the curve rises over a good share of the axis
        assert final / (hi - lo) > 0.3
    assert checks.problems(fig) == []


def test_coinciding_hit_curves_both_show():
    best, mean = restarts()
    gens, runs = best.shape
    same = reached_at(gens, runs, 5)
    ax = written(plot_convergence(best, mean, population=50,
                                  reached={"within 1%": same, "optimum": same})).axes[-1]
    near, hit = by_gid(ax, "reached_within 1%")[0], by_gid(ax, "reached_optimum")[0]
    assert np.array_equal(near.get_ydata(), hit.get_ydata())
    assert checks.drawn_over(hit, near) and near.get_linewidth() > hit.get_linewidth()


@pytest.mark.parametrize("gens, runs", [(51, 1), (1, 1), (2, 3), (0, 3)])
def test_small_histories_draw_cleanly(gens, runs):
    """One run (no band), one generation (a point), and no generation at all."""
    rng = np.random.default_rng(gens + runs)
    best = np.sort(rng.uniform(1000, 3000, (gens, runs)), axis=0)
    fig = written(plot_convergence(best, best * 0.5, optimum_fitness=3100.0,
                                   best_length=10000 / np.maximum(best, 1) - 1, optimum_length=2.2,
                                   reached={"optimum": np.full(runs, -1)}, population=50,
                                   title="small"))
    assert checks.problems(fig) == []
    assert checks.overlapping_texts(fig) == []
    assert len(fig.axes) == 3
