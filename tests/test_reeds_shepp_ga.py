"""The GA's Reeds–Shepp chromosomes: what they decode to, and that the search finds them.

A Reeds–Shepp chromosome (hga_jax/model/cars/reeds_shepp/reversing.py, legs.py) is a
free-turn one with seven-valued leg genes and the start's gear in the goal's gene.
Checked here: the turn table gives the decoder's values; every feasible chromosome
decodes to a path that passes the independent check (tests/_rs_check.py) and is never
shorter than the exact optimum (the genes express only the model's paths); the gears
follow the genes; the paths of quarter turns at the poses are expressed (a brute
force over short chromosomes reaches the exact optimum); the search hits it; and
nothing of this changes a forward car's run.
"""
from __future__ import annotations

import dataclasses
import functools
import itertools

import jax
import numpy as np
import pytest

import _rs_check
from hga_jax import scenario_from_dict
from hga_jax.model import car_model
from hga_jax.model.cars.reeds_shepp import reversing
from hga_jax.model.decode import decode_batch as _decode_batch
from hga_jax.model.exact import solve
from hga_jax.model.fitness import evaluate as _evaluate
from hga_jax.model.path import evaluate_path
from hga_jax.model.scenario import scenario_to_dict
from hga_jax.running.runner import run_many
from hga_jax.search import end_ops, leg_ops
from hga_jax.search.settings import RECOMMENDED, preset
from hga_jax.study import scenes

# Compiled once per shape: the eager decoder takes seconds for a few hundred rows.
decode_batch = jax.jit(_decode_batch, static_argnames="collision")
evaluate = jax.jit(_evaluate, static_argnames="collision")

RS = car_model.get("reeds-shepp")
VALUES = len(RS.genes[0].weights)


@functools.lru_cache(maxsize=None)
def _parking(kind: str, index: int, seed: int = 5, n: int = 9):
    """A parking-like scene (made once per process: the generator solves its optimum)."""
    d = scenes.generate(kind, n, seed, index, f"{kind}{index}")
    d["robot"]["car"] = "reeds-shepp"
    return scenario_from_dict(d, f"{kind}{index}")


def _random_chromosomes(rng, n: int, rows: int, touch: float = 0.25):
    perm = np.stack([rng.permutation(n) for _ in range(rows)]).astype(np.int32)
    labels = rng.choice([-1, 0, 1], size=(rows, n + 2),
                        p=[touch / 2, 1 - touch, touch / 2]).astype(np.int32)
    labels[:, 0] = rng.choice([-1, 1], rows)
    labels[:, -1] = rng.choice([-1, 1], rows)
    legs = rng.integers(0, VALUES, size=(rows, n + 2)).astype(np.int32)
    return perm, labels, legs


SCENES = [("slot", 0), ("wall", 0), ("behind", 1), ("slot", 3)]


@pytest.mark.parametrize(("kind", "index"), SCENES[:1])
def test_the_turn_table_gives_the_decoders_values(kind, index):
    sc = _parking(kind, index)
    perm, labels, legs = _random_chromosomes(np.random.default_rng(index), sc.n, 400)
    with jax.enable_x64(True):
        sa = RS.search_arrays(sc, np.float64, "full")
        assert sa.turns_free is not None  # the lookups, not the decoder, are tested
        e = evaluate(sa, perm, labels, "full", legs)
        d = decode_batch(sa, perm, labels, "full", legs)
    np.testing.assert_allclose(np.asarray(e.length), np.asarray(d.length), rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(np.asarray(e.violations), np.asarray(d.violations))


@pytest.mark.parametrize(("kind", "index"), SCENES[1:2])
def test_every_feasible_chromosome_is_a_checked_path_never_shorter_than_the_optimum(kind, index):
    sc = _parking(kind, index)
    d = scenario_to_dict(sc)
    opt = solve(sc, "full", car="reeds-shepp")
    perm, labels, legs = _random_chromosomes(np.random.default_rng(10 + index), sc.n, 6000, 0.1)
    sa = RS.search_arrays(sc, np.float32, "full")
    e = evaluate(sa, perm, labels, "full", legs)
    feasible = np.flatnonzero(np.asarray(e.violations) == 0)
    assert feasible.size >= 20
    cusps = 0
    for i in feasible[:60]:
        p = evaluate_path(sc, perm[i], labels[i], "full", legs[i])
        assert p.feasible and not p.violations_at
        assert p.length >= opt.length - 1e-9  # no chromosome beats the exact model
        assert _rs_check.problems(d, p.segments, p.length) == []
        cusps += sum(a.get("reverse", False) != b.get("reverse", False)
                     for a, b in zip(p.segments, p.segments[1:]))
    assert cusps > 0  # cusps were among the paths checked


def _gear_changes(segments):
    return sum(a.get("reverse", False) != b.get("reverse", False)
               for a, b in zip(segments, segments[1:]))


def test_gears_follow_the_genes():
    d = {"name": "open", "robot": {"radius": 0.09, "min_turn_radius": 0.2, "car": "reeds-shepp"},
         "start": {"x": 1.0, "y": 1.0, "heading_deg": 0.0},
         "goal": {"x": 2.2, "y": 1.9, "heading_deg": 90.0}, "obstacles": []}
    sc = scenario_from_dict(d, "open")
    perm = np.zeros(0, np.int32)
    # A tangent between the poses: forward with the goal's gene below 3, backward from 3.
    fwd = evaluate_path(sc, perm, [-1, -1], "full", [0, 0])
    back = evaluate_path(sc, perm, [-1, -1], "full", [0, reversing.BACKWARD])
    assert fwd.feasible and back.feasible
    assert not any(s.get("reverse") for s in fwd.segments)
    assert all(s.get("reverse") for s in back.segments)
    for path in (fwd, back):
        assert _rs_check.problems(d, path.segments, path.length) == []
    # A free circle between circles of opposite senses: one cusp, whatever the start gear.
    for gear in (0, reversing.BACKWARD):
        for gene in (1, 2, 3, 4):
            p = evaluate_path(sc, perm, [-1, 1], "full", [gene, gear])
            if p.feasible:
                assert _gear_changes(p.segments) == 1, (gene, gear)
                assert _rs_check.problems(d, p.segments, p.length) == []
    # Circles of one sense: genes 1-2 turn against them (no cusp), 3-4 with them (two).
    for gene, changes in ((1, 0), (2, 0), (3, 2), (4, 2)):
        p = evaluate_path(sc, perm, [1, 1], "full", [gene, 0])
        if p.feasible and len([s for s in p.segments if s.get("free")]):
            assert _gear_changes(p.segments) == changes, gene


def _brute(sc, most: int = 1):
    """The shortest feasible chromosome touching at most ``most`` obstacles (every label,
    gene and gear): ``(length, labels, legs)``."""
    n = sc.n
    rows = []
    for k in range(most + 1):
        for obs in itertools.permutations(range(n), k):
            perm = list(obs) + [i for i in range(n) if i not in obs]
            for labs in itertools.product([-1, 1], repeat=k + 2):
                lab = [labs[0], *labs[1:k + 1]] + [0] * (n - k) + [labs[-1]]
                for genes in itertools.product(range(VALUES), repeat=k + 1):
                    for gear in (0, reversing.BACKWARD):
                        rows.append((perm, lab, [*genes] + [0] * (n - k) + [gear]))
    perm, labels, legs = (np.asarray(v, np.int32) for v in zip(*rows))
    with jax.enable_x64(True):
        e = evaluate(RS.search_arrays(sc, np.float64, "full"), perm, labels, "full", legs)
    length = np.where(np.asarray(e.violations) == 0, np.asarray(e.length), np.inf)
    i = int(np.argmin(length))
    return float(length[i]), labels[i], legs[i]


@pytest.mark.parametrize(("kind", "index", "gene"), [("slot", 0, reversing.LEAVING),
                                                     ("wall", 0, reversing.ARRIVING)])
def test_quarter_turns_at_the_poses_express_the_parking_optimum(kind, index, gene):
    """Scenes whose optimum backs out of (or into) a pose with a quarter turn."""
    sc = _parking(kind, index)
    opt = solve(sc, "full", car="reeds-shepp")
    assert any(s.get("free") and abs(abs(s["sweep"]) - np.pi / 2) < 1e-6 for s in opt.segments)
    length, labels, legs = _brute(sc)
    assert length == pytest.approx(opt.length, rel=1e-9)
    assert gene in legs[np.flatnonzero(labels)[:-1]]  # by the quarter turn's gene


def test_end_settings_leave_a_forward_run_as_it_was():
    """The end move and its rate belong to the reversing car: a forward car's run (tight
    rope or free turns) draws the same words and makes the same runs whatever they say."""
    from hga_jax.search.variation import draw_rows

    other = {"end_mutation": "none", "pm_ends": 0.9, "ends_of_best": 5}
    for turns in ("tight-rope", "free"):
        st = dataclasses.replace(RECOMMENDED, turns=turns)
        assert draw_rows(9, st) == draw_rows(9, dataclasses.replace(st, **other))
    forward = dataclasses.replace(_parking("wall", 2), car="dubins")
    base = dataclasses.replace(preset("paper"), turns="free", collision="full", generations=6)
    a = run_many(forward, base, runs=4, seed=2, exact=False)
    b = run_many(forward, dataclasses.replace(base, **other), runs=4, seed=2, exact=False)
    for x, y in ((a.perm, b.perm), (a.labels, b.labels), (a.length, b.length), (a.legs, b.legs)):
        np.testing.assert_array_equal(x, y)
    assert a.legs.max() <= 2  # three values under free turns
    rs = dataclasses.replace(base, turns="reeds-shepp")
    assert draw_rows(9, rs) == draw_rows(9, dataclasses.replace(rs, end_mutation="none")) + 3


def test_leg_redraw_reaches_every_other_value():
    key = jax.random.key(0)
    genes = np.full((4000, 11), 3, np.int32)
    out = np.asarray(jax.vmap(lambda k, g: leg_ops.redraw(k, g, 1.0, VALUES))(
        jax.random.split(key, 4000), genes))
    counts = np.bincount(out.ravel(), minlength=VALUES)
    assert counts[3] == 0 and (counts[[0, 1, 2, 4, 5, 6]] > 0.15 * out.size / 6).all()


def test_the_end_move_redraws_an_end_or_the_direct_path():
    labels = np.array([1, -1, 0, 1, 0, -1], np.int32)
    legs = np.array([2, 1, 0, 4, 0, 1], np.int32)
    keys = jax.random.split(jax.random.key(5), 400)
    lab, lg = jax.vmap(lambda k: end_ops.redraw(k, jax.numpy.asarray(labels),
                                                jax.numpy.asarray(legs), VALUES))(keys)
    lab, lg = np.asarray(lab), np.asarray(lg)
    direct = (lab[:, 1:-1] == 0).all(axis=1)
    start = (lab[:, 1:] == labels[1:]).all(axis=1) & (lg[:, 1:-1] == legs[1:-1]).all(axis=1)
    kept = [0, 1, 2, 4, 5]  # all but the last touched position's gene (3)
    goal = (lab[:, :-1] == labels[:-1]).all(axis=1) & (lg[:, kept] == legs[kept]).all(axis=1)
    assert (start | goal | direct).all()
    for part in (start, goal, direct):
        assert 0.15 < part.mean() < 0.6
    assert (lg[direct][:, 1:-1] == legs[1:-1]).all()  # genes stay where labels are cleared


def test_the_last_children_are_the_parents_best_moved_at_its_ends():
    """``ends_of_best = k``: the last k children of a generation are the parents' best,
    each moved at one end (or both ends of the direct path); the other children are the
    children of ``k = 0``, bit for bit."""
    from hga_jax.search.state import Population
    from hga_jax.search.variation import _draw, _vary

    rng = np.random.default_rng(3)
    n, pop, k = 7, 12, 4
    perm, labels, legs = _random_chromosomes(rng, n, pop, touch=0.5)
    fitness = rng.random(pop).astype(np.float32)
    old = Population(perm, labels, fitness, fitness, np.zeros(pop, np.int32), legs)
    base = dataclasses.replace(preset("paper"), turns="reeds-shepp", population=pop)
    words = _draw(jax.random.key(4), n, base)
    vary = jax.jit(_vary, static_argnums=2)  # compiled: eager, the variation takes seconds
    plain = [np.asarray(x) for x in vary(words, old, base)]
    moved = [np.asarray(x) for x in vary(words, old, dataclasses.replace(base, ends_of_best=k))]
    for a, b in zip(plain, moved):
        np.testing.assert_array_equal(a[:-k], b[:-k])
    b = int(np.argmax(fitness))
    p, lab, lg = moved
    last = n + 1
    before = max(i for i in range(last) if labels[b, i] != 0 and i < last)
    assert (p[-k:] == perm[b]).all()
    for row_l, row_g in zip(lab[-k:], lg[-k:]):
        same = lambda idx: (row_l[idx] == labels[b, idx]).all() and (  # noqa: E731
            row_g[idx] == legs[b, idx]).all()
        start = same(slice(1, last)) and row_l[last] == labels[b, last]
        goal = same(slice(0, before)) and same(slice(before + 1, last)) and (
            row_l[before] == labels[b, before])
        direct = (row_l[1:last] == 0).all()
        assert start or goal or direct
    assert not all((lab[-k:] == labels[b]).all(axis=1) & (lg[-k:] == legs[b]).all(axis=1))


def test_the_recommended_search_hits_a_parking_optimum_from_the_command_line(tmp_path, capsys):
    """`hga-jax run` on a slot scene: the recommended search hits the Reeds-Shepp
    optimum, its best path passes the independent check, the summary counts its cusps,
    and its runs redraw and export with their gears (genes of seven values)."""
    import json

    import tomli_w

    from hga_jax.host.cli import main

    sc = _parking("slot", 0)
    path = tmp_path / "slot.toml"
    path.write_text(tomli_w.dumps(scenario_to_dict(sc)))
    out = tmp_path / "r"
    assert main(["run", str(path), "--runs", "12", "--seed", "3", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "cusp" in text.splitlines()[2] and "Reeds-Shepp optimum" in text
    doc = json.loads((out / "result.json").read_text())
    assert doc["settings"]["car"] == "reeds-shepp" and doc["settings"]["turns"] == "reeds-shepp"
    opt, best = doc["optimum"]["length"], doc["best"]
    hits = [r["feasible"] and r["length"] <= opt * (1 + 1e-9) for r in doc["per_run"]]
    assert sum(hits) >= 9  # 75 % of the runs
    assert best["length"] == pytest.approx(opt, rel=1e-9)
    assert any(seg.get("reverse") for seg in best["segments"])
    assert _rs_check.problems(scenario_to_dict(sc), best["segments"], best["length"]) == []
    legs = [r["legs"] for r in doc["per_run"]]
    assert all(len(g) == sc.n + 2 and max(g) < VALUES for g in legs)
    k = best["run"]
    assert main(["plot", str(out / "result.json"), "--run", str(k)]) == 0
    assert main(["export", str(out / "result.json"), "--run", str(k)]) == 0
    capsys.readouterr()
    poses = json.loads((out / f"poses_run{k}.json").read_text())
    gear = poses["columns"].index("gear")
    gears = {row[gear] for row in poses["poses"]}
    assert gears == {1.0, -1.0}  # the slot optimum backs up and drives forward
