"""Figures as a user reads them: a Reeds-Shepp path whose shortest pieces sit under the
start, goal and cusp marks (drawn above the poses, named clearly, shown enlarged, the
axes fitting the field); convergence with the restarts marked and the current population
told from the best so far; a plot title that names the optimum once; a time-to-target
caption that promises only the lines drawn; a scaling figure and table of one scene
size, peers named as themselves, one exact time per scene; the paper's Fig. 4 with the
typical run beside the best.
"""
from __future__ import annotations

import inspect
import json
import math
from types import SimpleNamespace
from unittest import mock

import numpy as np
import pandas as pd
import pytest
from matplotlib.transforms import Bbox

import _figure_checks as checks
from _figure_checks import by_gid, legend_labels, written
from hga_jax import scenario_from_dict
from hga_jax.host.plots import plot_convergence, plot_path, save_figure
from hga_jax.host.plots.convergence import restarts_of
from hga_jax.host.plots.path import POSE_Z, PATH_Z
from hga_jax.model.exact import solve

SAVED_DPI = inspect.signature(save_figure).parameters["dpi"].default
ROBOCUP = "configs/scenarios/robocup_paper.toml"
RHO = r"free turn (radius $\rho$)"

# A "wall" scene of the Reeds-Shepp study (family seed 73, scene 0): its optimum backs
# out of the start (a 6.5 mm arc), round robot 8, through a free turn to a cusp, and
# drives forward 16.5 mm to the goal.
WALL = {"name": "wall_n009_000",
        "robot": {"radius": 0.09, "min_turn_radius": 0.15, "car": "reeds-shepp"},
        "start": {"x": 0.3668, "y": 0.2235, "heading_deg": -102.83},
        "goal": {"x": 0.9171, "y": 0.865, "heading_deg": 129.84},
        "obstacles": [{"x": x, "y": y, "radius": 0.09} for x, y in (
            (0.8711, 0.2025), (2.5142, 1.7768), (1.2774, 1.4294), (1.6129, 1.3277),
            (0.4134, 1.7414), (1.7567, 0.9648), (0.874, 2.0741), (0.5932, 0.4608),
            (0.7467, 1.2008))],
        "field": {"xmin": 0.0, "xmax": 2.8, "ymin": 0.0, "ymax": 2.3, "keep_inside": True}}


def _length(xy) -> float:
    return float(np.sum(np.hypot(*np.diff(np.asarray(xy, float), axis=0).T)))


# -- 1. Reeds-Shepp path plots ---------------------------------------------------------------

@pytest.fixture(scope="module")
def wall():
    sc = scenario_from_dict(WALL, "wall")
    opt = solve(sc)
    assert opt.turns == "reeds-shepp" and opt.details["cusps"] == 1
    assert opt.length == pytest.approx(0.996470, abs=1e-6)
    return sc, opt, written(plot_path(sc, opt.segments, touched=opt.touched))


def test_reeds_shepp_legend_names_each_kind_of_piece_once(wall):
    sc, opt, fig = wall
    ax = fig.axes[0]
    assert legend_labels(ax) == [
        "start", "goal", "arc, driven backward", "line, driven backward",
        f"{RHO}, driven backward", "arc, driven forward", "cusp", "obstacle (robot)",
        "model circle", r"turning circles ($\rho$)", "touched (CW/CCW)", "field",
        "field shrunk by r", "shown enlarged below"]
    # each entry is a kind drawn: the pieces of the optimum, in these kinds
    kinds = [("free " if s.get("free") else "") + s["type"] + (" back" if s.get("reverse") else "")
             for s in opt.segments]
    assert kinds == ["arc back", "line back", "arc back", "line back", "free arc back", "arc"]


def test_reeds_shepp_pieces_lie_over_the_pose_marks(wall):
    _, opt, fig = wall
    ax = fig.axes[0]
    pieces = [ln for ln in ax.get_lines() if ln.get_gid() in
              ("arc", "line", "reverse_arc", "reverse_line", "free_reverse_arc")]
    assert len(pieces) == len(opt.segments)
    poses = [a for gid in ("start", "goal", "start_arrow", "goal_arrow") for a in by_gid(ax, gid)]
    assert len(poses) == 4
    for piece in pieces:
        for pose in poses:
            assert checks.drawn_over(piece, pose)
    assert PATH_Z > POSE_Z
    for arrow in by_gid(ax, "start_arrow") + by_gid(ax, "goal_arrow"):
        assert arrow.get_alpha() < 1


def test_reeds_shepp_axes_fit_the_field(wall):
    """The field is 2.8 by 2.3 m: the view keeps a small margin round it, not the -0.5 to
    2.8 m of a box stretched by the legend beside it."""
    _, _, fig = wall
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    for lo, hi, size in ((x0, x1, 2.8), (y0, y1, 2.3)):
        assert -0.05 * size <= lo < 0 and size < hi <= 1.05 * size
    assert checks.problems(fig) == []
    assert checks.overlapping_texts(fig) == []
    assert checks.legend_margin(fig) >= 4.0


def test_reeds_shepp_short_pieces_show_enlarged(wall):
    """The 6.5 mm backward arc at the start and the 16.5 mm forward arc into the goal are
    a few pixels long on the scene, under the start's dot and the cusp's ring; each is
    shown again enlarged (framed in its pose's colour, the cusp's black) below the
    legend, where it is tens of points long, clear of the legend and on the page."""
    sc, opt, fig = wall
    ax = fig.axes[0]
    insets = [a for a in ax.child_axes if a.get_gid() == "zoom"]
    assert [a.get_title().split("\n")[0] for a in insets] == ["start", "cusp and goal"]
    assert len(by_gid(ax, "zoom_box")) == 2
    r = checks._renderer(fig)
    legend = ax.get_legend().get_window_extent(r)
    pt = SAVED_DPI / 72
    first, last = opt.segments[0], opt.segments[-1]
    for inset, seg, gid in ((insets[0], first, "reverse_arc"), (insets[1], last, "arc")):
        box = inset.get_window_extent(r)
        assert box.y1 < legend.y0 and not box.overlaps(ax.bbox)
        assert Bbox.intersection(box, fig.bbox).width == pytest.approx(box.width)
        (main,) = [ln for ln in ax.get_lines() if ln.get_gid() == gid
                   and np.allclose(ln.get_xydata()[0], _first_point(seg))]
        (big,) = [ln for ln in inset.get_lines() if ln.get_gid() == gid
                  and np.allclose(ln.get_xydata()[0], _first_point(seg))]
        on_scene = _length(ax.transData.transform(main.get_xydata())) / pt
        enlarged = _length(inset.transData.transform(big.get_xydata())) / pt
        assert on_scene < 10 and enlarged > 25, (on_scene, enlarged)
        x0, x1 = inset.get_xlim()
        y0, y1 = inset.get_ylim()
        xy = big.get_xydata()
        assert np.all((xy[:, 0] > x0) & (xy[:, 0] < x1) & (xy[:, 1] > y0) & (xy[:, 1] < y1))
    assert checks.texts_off_canvas(fig) == []


def _first_point(seg):
    if seg["type"] == "line":
        return seg["start"]
    a = seg["start_angle"]
    return np.asarray(seg["center"]) + seg["radius"] * np.array([math.cos(a), math.sin(a)])


def test_forward_path_keeps_its_plain_names_and_no_enlargement():
    from hga_jax.host.config import load_scenario

    sc = load_scenario(ROBOCUP)
    opt = solve(sc)
    ax = written(plot_path(sc, opt.segments, touched=opt.touched)).axes[0]
    labels = legend_labels(ax)
    assert labels[2:4] == ["path arc", "path line"]
    assert not any("driven" in t or "enlarged" in t for t in labels)
    assert not [a for a in ax.child_axes if a.get_gid() == "zoom"]


# -- 2. convergence ----------------------------------------------------------------------------

def test_restarts_follow_the_ga_rule_by_hand():
    """R = 4. Run 0 improves in generations 0-2, then never: it restarts at 8, 12, 16 (at
    4 its last gain, generation 2, is under 4 generations back). Run 1 improves every
    generation: never. Run 2 improves at 0 and 9: at 4 and 8; after 9, at 16 only."""
    g = np.arange(18, dtype=float)
    run0 = np.minimum(g, 2)
    run1 = g.copy()
    run2 = np.where(g >= 9, 5.0, 1.0)
    best = np.stack([run0, run1, run2], axis=1)
    best[[8, 12], 0] = -3.0  # a fresh population's best is lower: the best so far is not
    got = restarts_of(best, 4)
    assert [np.flatnonzero(got[:, k]).tolist() for k in range(3)] == [[8, 12, 16], [], [4, 8, 16]]
    assert not restarts_of(best, 0).any()


@pytest.fixture(scope="module")
def restarting_runs():
    import hga_jax as hg
    from hga_jax.host.config import load_scenario
    from hga_jax.search.settings import GASettings

    sc = load_scenario(ROBOCUP)
    st = GASettings(population=20, generations=40, elites=1, restart_after=4)
    return hg.run_many(sc, st, seed=0, runs=4)


def test_restarts_read_from_the_history_are_the_searchs(restarting_runs):
    """With elites kept, a population's best falls only where the run restarted: every
    fall is at a restart found by the rule, and the best so far is the running maximum."""
    res = restarting_runs
    h = res.history
    fresh = restarts_of(h["best_fitness"], res.settings.restart_after)
    best = h["best_fitness"]
    falls = np.zeros_like(fresh)
    falls[1:] = best[1:] < best[:-1]
    assert falls.any() and fresh.sum() >= falls.sum()
    assert not (falls & ~fresh).any()
    assert np.array_equal(np.maximum.accumulate(best, axis=0), h["best_so_far_fitness"])


def test_run_convergence_marks_restarts_and_names_its_curves(restarting_runs):
    from hga_jax.host.report import run_figures

    res = restarting_runs
    fig = written(run_figures(res)["convergence.png"])
    ax = fig.axes[0]
    fresh = restarts_of(res.history["best_fitness"], 4)
    lines = by_gid(ax, "restart")
    assert [ln.get_xdata()[0] for ln in lines] == np.flatnonzero(fresh.any(axis=1)).tolist()
    labels = legend_labels(ax)
    assert labels[:3] == ["best of the current population", "mean of the current population",
                          "best so far"]
    restart = [t for t in labels if t.startswith("restart")]
    assert restart == [f"restart (no gain in 4 generations:\na new population; "
                       f"{int(fresh.sum())} in all)"]
    assert "median over 4 runs" in ax.get_legend().get_title().get_text()
    (so_far,) = by_gid(ax, "best_so_far_median")
    assert np.allclose(so_far.get_ydata(), np.median(res.history["best_so_far_fitness"], axis=1))
    assert legend_labels(fig.axes[1])[0] == "best so far"
    assert checks.problems(fig) == [] and checks.overlapping_texts(fig) == []


def test_convergence_without_restarts_draws_no_restart_lines():
    best = np.sort(np.random.default_rng(2).uniform(1000, 3000, (25, 5)), axis=0)
    ax = plot_convergence(best, best / 2).axes[0]
    assert not by_gid(ax, "restart")
    assert not any(t.startswith("restart") for t in ax.get_legend_handles_labels()[1])


# -- 3. plot --with-optimum on an exact result ---------------------------------------------------

def test_with_optimum_on_an_exact_result_names_the_optimum_once(tmp_path):
    from hga_jax.host.cli import main
    from hga_jax.host.report import redraw

    assert main(["exact", ROBOCUP, "--out", str(tmp_path / "e"), "--quiet"]) == 0
    res = str(tmp_path / "e" / "result.json")
    length = json.loads(open(res).read())["optimum"]["length"]
    title = redraw(res, with_optimum=True).axes[0].get_title()
    assert title.count(f"{length:.4f}") == 1, title
    assert title.count("optimum") == 2 and "dashed: the same optimum" in title
    assert redraw(res).axes[0].get_title().count(f"{length:.4f}") == 1


# -- 4. time to target ---------------------------------------------------------------------------

def _times(with_exact: bool) -> pd.DataFrame:
    rng = np.random.default_rng(1)
    rows = [{"group": "g", "config": "recommended", "solver": "hga", "time_s": 0.05,
             "time_1pct": float(t), "time_hit": float(2 * t)} for t in rng.uniform(1e-3, 1e-2, 8)]
    if with_exact:
        rows.append({"group": "g", "config": "exact", "solver": "exact", "time_s": 0.04,
                     "time_1pct": 0.04, "time_hit": 0.04})
    return pd.DataFrame(rows)


@pytest.mark.parametrize("with_exact", [False, True])
def test_time_ecdf_caption_names_the_dashed_line_only_where_drawn(with_exact):
    from hga_jax.study import figures

    tab = _times(with_exact)
    configs = list(dict.fromkeys(tab["config"]))
    fig = written(figures.time_to_target_figure(tab, configs))
    caption = fig._suptitle.get_text().replace("\n", " ")
    assert "hindsight" in caption
    dashed = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_gid() == "exact"]
    assert ("Dashed vertical line" in caption) == with_exact == bool(dashed)


# -- 5. scaling -----------------------------------------------------------------------------------

CONFIGS = [SimpleNamespace(label="recommended", solver="hga"),
           SimpleNamespace(label="OMPL BIT*, 1 s", solver="ompl"),
           SimpleNamespace(label="exact", solver="exact")]
EXACT_S = {  # per configuration and scene: the seconds of the solve its cell made
    "recommended": {"behind": 0.065, "slot": 0.096},
    "OMPL BIT*, 1 s": {"behind": 0.041, "slot": 0.119},
    "exact": {"behind": 0.0435, "slot": 0.063}}


def _scaling_study(configs, sizes=(9,)):
    rows, docs = [], []
    for c in configs:
        runs = {"hga": 4, "ompl": 2, "exact": 1}[c.solver]
        for fam in ("behind", "slot"):
            for n in sizes:
                scene = f"{fam}_n{n:03d}"
                docs.append({"config": c.label, "solver": c.solver, "family": fam,
                             "obstacles": n, "scenario": scene,
                             "exact_s": EXACT_S[c.label][fam] * n / 9})
                for k in range(runs):
                    hit = c.solver != "ompl" or k == 0
                    rows.append({
                        "config": c.label, "family": fam, "obstacles": n, "scenario": scene,
                        "gap": 0.0 if hit else 0.03, "hit": hit,
                        "time_s": {"hga": 0.05, "ompl": 1.1,
                                   "exact": EXACT_S["exact"][fam]}[c.solver],
                        "evaluations": 7550.0 if c.solver == "hga" else None,
                        "evaluations_hit": (300.0 * (k + 1) if c.solver == "hga" else None)})
    return SimpleNamespace(configs=configs), pd.DataFrame(rows), docs


def _scaling(tmp_path, configs, sizes=(9,)):
    from hga_jax.study import analyses

    study, tab, docs = _scaling_study(configs, sizes)
    figs = []
    with mock.patch.object(analyses, "save", lambda fig, path: figs.append(fig) or path):
        analyses.scaling(study, tab, docs, [], str(tmp_path))
    table = pd.read_csv(tmp_path / "scaling.csv")
    return written(figs[0]), table, (tmp_path / "scaling.md").read_text()


def test_scaling_of_one_size_draws_a_strip_per_configuration(tmp_path):
    fig, table, _ = _scaling(tmp_path, CONFIGS)
    a1, a2 = fig.axes
    names = ["GA: recommended", "OMPL BIT*, 1 s", "exact"]
    assert [t.get_text() for t in a1.get_xticklabels()] == names
    assert [t.get_text() for t in a2.get_xticklabels()] == names
    assert "every scene has 9 obstacles" in a1.get_xlabel()
    for ax in (a1, a2):  # each configuration's families side by side, never on one spot
        for c in CONFIGS:
            xs = {float(x) for ln in ax.get_lines() if ln.get_gid() == c.label
                  for x in ln.get_xdata()}  # an error bar's caps share its point's x
            assert len(xs) == 2
            k = names.index(c.label if c.solver != "hga" else f"GA: {c.label}")
            assert all(abs(x - k) < 0.4 for x in xs)
    legend = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert legend == ["behind", "slot"]
    assert not any(t.startswith("GA: OMPL") or t.startswith("GA: exact")
                   for t in legend + [t.get_text() for t in a1.get_xticklabels()])
    assert checks.problems(fig) == [] and checks.overlapping_texts(fig) == []


def test_scaling_of_several_sizes_names_peers_as_themselves(tmp_path):
    fig, _, _ = _scaling(tmp_path, CONFIGS[:2], sizes=(9, 15))
    legend = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert legend == ["GA: recommended, behind", "GA: recommended, slot",
                      "OMPL BIT*, 1 s, behind", "OMPL BIT*, 1 s, slot",
                      "exact solver (its time per scene), behind",
                      "exact solver (its time per scene), slot"]
    a1, a2 = fig.axes
    assert a1.get_xlabel() == "obstacles" and list(a1.get_xticks()) == [9, 15]
    (ref,) = [ln for ln in a2.get_lines() if ln.get_gid() == "exact solver"
              and ln.get_marker() == "o"]
    # no exact configuration: the median of the solves of each scene (65 and 41 ms at 9)
    assert ref.get_ydata().tolist() == pytest.approx([53.0, 53.0 * 15 / 9])
    assert checks.problems(fig) == []


def test_scaling_table_has_one_exact_time_per_scene_and_dashes_for_none(tmp_path):
    _, table, md = _scaling(tmp_path, CONFIGS)
    for fam, ms in (("behind", 43.5), ("slot", 63.0)):  # the exact solver's own cell
        assert table[table["family"] == fam]["exact_ms_median"].tolist() == pytest.approx([ms] * 3)
    lines = [ln for ln in md.splitlines() if ln.startswith("| ")]
    head = [c.strip() for c in lines[0].strip("|").split("|")]
    cells = {(r[0], r[1]): dict(zip(head, r)) for r in (  # (the rule under the head: "|-")
        [c.strip() for c in ln.strip("|").split("|")] for ln in lines[1:])}
    assert len(cells) == 6
    for (config, fam), row in cells.items():
        assert row["exact ms/scene"] == {"behind": "43.50", "slot": "63.00"}[fam]
        counted = config == "recommended"
        for col in ("evaluations per run", "median evaluations to the hit",
                    "evaluations for 99% of runs to hit"):
            assert (row[col] != "-") == counted, (config, col, row[col])
            assert "inf" not in row[col]
    assert cells[("recommended", "behind")]["evaluations per run"] == "7,550"
    assert cells[("recommended", "behind")]["median evaluations to the hit"] == "750"
    assert '"-": none' in md


# -- 6. the paper's Fig. 4 ------------------------------------------------------------------------

def test_typical_run_is_the_median_of_the_ranked_runs():
    from hga_jax.study.analyses import typical_run

    doc = {"columns": {"run": [10, 11, 12, 13, 14],
                       "length": [2.3, 2.25, 9.0, 2.4, 2.5], "violations": [0, 0, 2, 0, 0]}}
    assert typical_run(doc) == 3  # ranked 2.25, 2.3, 2.4, 2.5, then the infeasible one
    doc["columns"]["run"].append(15)
    doc["columns"]["length"].append(2.26)
    doc["columns"]["violations"].append(0)
    assert typical_run(doc) == 0  # the lower median of six: 2.25, 2.26, (2.3), 2.4, ...


def test_paper_fig4_shows_the_typical_run_beside_the_best(tmp_path):
    """A small study of the paper's GA: Fig. 4 draws the best run and the median run (run
    again from its seed), each titled with its run, length and gap, and says how many
    runs reached the optimum."""
    from hga_jax.study import analyses, run_study
    from hga_jax.study.config import load_study

    path = tmp_path / "tiny.toml"
    path.write_text(f'name = "tiny"\nseed = 0\nruns = 6\nscenarios = ["{_abs(ROBOCUP)}"]\n'
                    'analyses = ["paper"]\n[ga]\npopulation = 20\ngenerations = 10\n'
                    '[[configs]]\nlabel = "paper"\n')
    figs = {}
    real_save = analyses.save
    def keep(fig, p):
        figs[p.split("/")[-1]] = fig
        return real_save(fig, p)

    with mock.patch.object(analyses, "save", keep):
        out = run_study(load_study(str(path)), out=str(tmp_path / "out"), progress=False)
    (doc,) = out.docs
    fig = written(figs["paper_fig4_best_path.png"])
    axes = [ax for ax in fig.axes]
    assert len(axes) == 2
    c, opt = doc["columns"], doc["optimum"]
    k = analyses.typical_run(doc)
    j = doc["best"]["run"]
    hits = sum(c["hit"])

    def words(length, violations):
        if violations:
            return "infeasible"
        gap = length / opt - 1
        return "the optimum" if gap < 1e-6 else f"{100 * gap:.2f} % over the optimum"

    i = c["run"].index(j)
    assert axes[0].get_title() == (f"best of 6 runs (run {j}): {c['length'][i]:.4f} m, "
                                   f"{words(c['length'][i], c['violations'][i])}")
    assert axes[1].get_title().startswith(
        f"typical run (run {c['run'][k]}, the median of 6): {c['length'][k]:.4f} m, "
        f"{words(c['length'][k], c['violations'][k])}")
    assert fig._suptitle.get_text() == (f"robocup_paper: optimum {opt:.4f} m, reached by "
                                        f"{hits} of 6 runs")
    # the typical panel draws the run's own path: its pieces add up to the cell's length
    pieces = [ln for ln in axes[1].get_lines() if ln.get_gid() in ("arc", "line")]
    if not c["violations"][k]:
        assert sum(_length(ln.get_xydata()) for ln in pieces) == pytest.approx(
            c["length"][k], rel=1e-3)
    assert checks.texts_off_canvas(fig) == []


def _abs(p: str) -> str:
    import os

    return os.path.abspath(p)
