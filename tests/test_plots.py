"""Figures: the drawn path follows the segments; convergence shows medians and the optimum."""
import math

import numpy as np
import pytest

from hga_jax.path import evaluate_path
from hga_jax.plots import plot_convergence, plot_path, save_figure
from hga_jax.scenario import Field, Scenario


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
    assert save_figure(fig, tmp_path / "c.png").stat().st_size > 10_000
