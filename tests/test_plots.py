"""Figures: the drawn path follows the segments; convergence shows medians and the optimum."""
import math

import numpy as np
import pytest

from hga_jax.model.path import evaluate_path
from hga_jax.host.plots import plot_convergence, plot_path, save_figure
from hga_jax.model.scenario import Field, Scenario


@pytest.fixture()
def scene():
    return Scenario("demo", 0.09, 0.2, (0.3, 0.5, 0.0), (2.5, 0.5, 0.0),
                    np.array([[1.4, 0.5], [2.0, 1.2]]), np.full(2, 0.09), Field(0, 3, 0, 1.6, True))


def _by_gid(ax, gid):
    return [a for a in ax.get_children() if a.get_gid() == gid]


def test_path_artists_follow_the_segments(scene, tmp_path):
    path = evaluate_path(scene, [0, 1], [1, 1, 0, 1])  # over obstacle 1 (CW)
    assert path.feasible
    fig = plot_path(scene, path.segments, touched=path.touched)
    ax = fig.axes[0]
    arcs, lines = _by_gid(ax, "arc"), _by_gid(ax, "line")
    kinds = [s["type"] for s in path.segments]
    assert len(arcs) == kinds.count("arc") and len(lines) == kinds.count("line")
    for art, seg in zip(arcs, [s for s in path.segments if s["type"] == "arc"]):
        (cx, cy), r, a, s = seg["center"], seg["radius"], seg["start_angle"], seg["sweep"]
        x, y = art.get_data()
        assert (x[0], y[0]) == pytest.approx((cx + r * math.cos(a), cy + r * math.sin(a)), abs=1e-9)
        assert (x[-1], y[-1]) == pytest.approx((cx + r * math.cos(a + s), cy + r * math.sin(a + s)),
                                               abs=1e-9)
    for art, seg in zip(lines, [s for s in path.segments if s["type"] == "line"]):
        x, y = art.get_data()
        assert np.allclose(np.c_[x, y], [seg["start"], seg["end"]])
    assert len(_by_gid(ax, "obstacle")) == 2 and len(_by_gid(ax, "model_circle")) == 2
    assert len(_by_gid(ax, "turning_circle")) == 4
    assert len(_by_gid(ax, "touched")) == 1  # the label next to obstacle 1
    out = save_figure(fig, tmp_path / "path.png")
    assert out.stat().st_size > 10_000


def test_hand_computed_path(tmp_path):
    """Start north at (0,0), CW quarter to (1,1), line to (3,1), CW quarter down to (4,0)."""
    sc = Scenario("hand", 0.1, 1.0, (0.0, 0.0, math.pi / 2), (4.0, 0.0, -math.pi / 2),
                  np.array([[2.0, -0.6], [5.0, 3.0], [-1.0, 2.0]]), np.full(3, 0.1), None)
    segs = [{"type": "arc", "center": [1.0, 0.0], "radius": 1.0, "start_angle": math.pi,
             "sweep": -math.pi / 2},
            {"type": "line", "start": [1.0, 1.0], "end": [3.0, 1.0]},
            {"type": "arc", "center": [3.0, 0.0], "radius": 1.0, "start_angle": math.pi / 2,
             "sweep": -math.pi / 2}]
    fig = plot_path(sc, segs, touched=[{"obstacle": 2, "label": -1}], title="length 5.142 m, feasible")
    ax = fig.axes[0]
    (a1, a2), (line,) = _by_gid(ax, "arc"), _by_gid(ax, "line")
    xy1, xy2 = np.c_[a1.get_data()], np.c_[a2.get_data()]
    assert np.allclose(xy1[[0, -1]], [[0, 0], [1, 1]], atol=1e-9, rtol=0)
    assert np.allclose(xy2[[0, -1]], [[3, 1], [4, 0]], atol=1e-9, rtol=0)
    assert np.allclose(np.hypot(xy1[:, 0] - 1, xy1[:, 1]), 1.0) and len(xy1) > 10
    assert np.all(xy1[:, 1] >= -1e-12) and np.all(xy2[:, 0] >= 3 - 1e-12)  # the short way round
    assert np.array_equal(np.c_[line.get_data()], [[1, 1], [3, 1]])
    assert len(_by_gid(ax, "obstacle")) == 3 and len(_by_gid(ax, "model_circle")) == 3
    assert not _by_gid(ax, "field") and not _by_gid(ax, "field_inner")
    assert [t.get_text() for t in _by_gid(ax, "touched")] == ["CCW"]
    assert ax.get_title() == "length 5.142 m, feasible"
    labels = ax.get_legend_handles_labels()[1]
    assert labels.count("path arc") == 1 and labels.count("path line") == 1
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    assert x0 < -1.0 and x1 > 5.0 and y0 < -1.0 and y1 > 3.0  # goal circle, obstacles in view
    assert save_figure(fig, tmp_path / "hand.png").stat().st_size > 10_000


def test_plot_into_given_axes(scene):
    from matplotlib.figure import Figure

    fig = Figure()
    a1, a2 = fig.subplots(1, 2)
    assert plot_path(scene, [], ax=a2) is fig
    assert a2.get_title() == "demo" and not a1.patches
    assert len(_by_gid(a2, "field")) == 1 and len(_by_gid(a2, "field_inner")) == 1
    with pytest.raises(ValueError):
        plot_path(scene, [{"type": "spline"}])


def test_scene_without_a_path(scene):
    ax = plot_path(scene, []).axes[0]
    assert not _by_gid(ax, "arc") and not _by_gid(ax, "line")


@pytest.mark.parametrize("runs", [1, 10])
def test_convergence_medians_and_optimum(runs, tmp_path):
    rng = np.random.default_rng(runs)
    best = np.sort(rng.uniform(1000, 3000, (21, runs)), axis=0)
    mean = best * 0.6
    length = 10000 / best - 1
    fig = plot_convergence(best, mean, optimum_fitness=3100.0, best_length=length,
                           optimum_length=2.2)
    ax, ax2 = fig.axes
    med = _by_gid(ax, "best_median")[0].get_ydata()
    assert np.allclose(med, np.median(best, axis=1))
    assert np.allclose(_by_gid(ax, "mean_median")[0].get_ydata(), np.median(mean, axis=1))
    assert _by_gid(ax, "optimum")[0].get_ydata()[0] == 3100.0
    assert _by_gid(ax2, "optimum_length")[0].get_ydata()[0] == 2.2
    band_y = np.concatenate([p.vertices[:, 1] for p in _by_gid(ax, "best_band")[0].get_paths()])
    q1, q3 = np.percentile(best, [25, 75], axis=1)
    assert band_y.min() == pytest.approx(q1.min()) and band_y.max() == pytest.approx(q3.max())
    if runs == 1:  # the band collapses onto the single run
        assert np.allclose(q1, med) and np.allclose(q3, med)
    assert save_figure(fig, tmp_path / "c.png").stat().st_size > 10_000


def test_convergence_single_panel():
    best = np.linspace(1000, 2000, 11)[:, None]
    fig = plot_convergence(best, best / 2, title="one run")
    (ax,) = fig.axes
    assert not _by_gid(ax, "optimum")
    assert np.array_equal(_by_gid(ax, "best_median")[0].get_xdata(), np.arange(11))
    assert fig._suptitle.get_text() == "one run"


def test_violations_are_located_and_marked(scene):
    # Straight on through obstacle 1 (label 0): the start-goal line crosses it.
    path = evaluate_path(scene, [0, 1], [-1, 0, 0, 1])
    assert path.violations == 1
    assert path.violations_at == [{"kind": "obstacle", "segment": 0, "obstacle": 1}]
    assert path.segments[0]["type"] == "line"
    ax = plot_path(scene, path.segments, violations_at=path.violations_at).axes[0]
    (piece,) = _by_gid(ax, "violation_piece")
    assert np.allclose(np.c_[piece.get_data()], [path.segments[0]["start"], path.segments[0]["end"]])
    (ring,) = _by_gid(ax, "violation_obstacle")
    assert ring.center == pytest.approx((1.4, 0.5)) and ring.get_edgecolor()[:3] == (1.0, 0.0, 0.0)
    (cross,) = _by_gid(ax, "violation_point")
    assert (cross.get_xdata()[0], cross.get_ydata()[0]) == pytest.approx((1.4, 0.5), abs=1e-9)
    assert "violation: piece" in ax.get_legend_handles_labels()[1]


def test_every_violation_is_located():
    from hga_jax.host.config import load_scenario

    rng = np.random.default_rng(7)
    for name in ("robocup_paper", "overlapping"):
        sc = load_scenario(f"configs/scenarios/{name}.toml")
        kinds = set()
        for collision in ("full", "paper"):
            for _ in range(25):
                labels = rng.integers(-1, 2, sc.n + 2)
                labels[[0, -1]] = rng.choice([-1, 1], 2)
                p = evaluate_path(sc, rng.permutation(sc.n), labels, collision)
                assert len(p.violations_at) == p.violations
                kinds |= {v["kind"] for v in p.violations_at}
                for v in p.violations_at:
                    assert v["segment"] is None or 0 <= v["segment"] < len(p.segments)
                    assert (v["obstacle"] is None) == (v["kind"] != "obstacle")
        assert "obstacle" in kinds


def test_optimum_overlay_and_touched_format(scene):
    path = evaluate_path(scene, [0, 1], [1, 1, 0, 1])
    other = evaluate_path(scene, [1, 0], [1, 0, 0, 1])
    ax = plot_path(scene, other.segments, optimum=path.segments, touched=path.touched).axes[0]
    assert len(_by_gid(ax, "optimum_path")) == len(path.segments)
    assert path.touched == [(1, 1)] and path.to_dict()["touched"] == [{"obstacle": 1, "label": 1}]
    assert path.touched[0].obstacle == 1 and path.touched[0].label == 1
    for same in (path.touched, path.to_dict()["touched"]):  # Python's pairs, the file's items
        ax = plot_path(scene, path.segments, touched=same).axes[0]
        assert [t.get_text() for t in _by_gid(ax, "touched")] == ["CW"]
    with pytest.raises(TypeError, match="touched: items must be"):
        plot_path(scene, [], touched=["1CW"])
    with pytest.raises(ValueError, match=r"touched: obstacle must be in 1\.\.2, got number 3"):
        plot_path(scene, [], touched=[{"obstacle": 3, "label": 1}])
