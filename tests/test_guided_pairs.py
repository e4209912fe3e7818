"""The guided move with paired flips (hga_jax/search/guided_pairs.py): each version's
score against the leg score of the chromosome it makes (float64), its arc terms against a
plain pass over the chromosomes, the choice of the best of the fifty, and the GA's
population form against the one-chromosome move."""
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.host.config import load_scenario
from hga_jax.search import guided, guided_pairs, path_ops, registry, rng
from hga_jax.search.path_ops import Plan
from test_guided import _random, arc_violated

SCENE = "configs/scenarios/overlapping.toml"  # overlapping circles: arcs with violations


def _legs(dtype=np.float64):
    sc = load_scenario(SCENE)
    legs = sc.search_arrays(dtype, with_legs=True).legs
    return sc, legs._replace(penalty=legs.penalty * 10)


def _versions(plan, p, lab, legs, arcs=False):
    """Per version (2, ...): its score (the candidate's change plus the flip's), the
    chromosome it makes, and whether it exists; and the candidate alone, made."""
    v, w = path_ops.view(p, lab, legs), guided.weights(legs)
    at = guided.places(plan, p, v)
    table, charge = (legs.arcs, 0.7 * legs.penalty) if arcs else (None, 0.0)
    alone = guided.change(plan, p, lab, v, w, table, charge, at)
    extra, ends = guided_pairs.flips(plan, at, lab, v, w, table, charge)
    made = [path_ops.apply(p, lab, plan._replace(end=e)) for e in ends]
    return alone + extra, made, jnp.isfinite(extra), path_ops.apply(p, lab, plan)


@pytest.mark.parametrize("plan", path_ops.PLANS, ids=lambda f: f.__name__)
def test_a_version_changes_the_leg_score_by_its_score(plan):
    """Candidate and flip together change the leg score by exactly what the chromosome
    they make scores more, whichever neighbour is flipped."""
    sc, legs = _legs()
    perm, labels = _random(sc.n, 200, seed=5)
    keys = jax.random.split(rng.key(4), len(perm))
    with jax.enable_x64(True):
        def one(k, p, lab):
            score, made, on, _ = _versions(plan(k, p, lab, legs), p, lab, legs)
            return (score, on, guided.leg_score(p, lab, legs),
                    jnp.stack([guided.leg_score(*m, legs) for m in made]))
        score, on, before, after = jax.jit(jax.vmap(one))(keys, perm, labels)
    score, on = np.asarray(score), np.asarray(on)
    want = np.asarray(after) - np.asarray(before)[:, None]
    np.testing.assert_allclose(score[on], want[on], rtol=0, atol=1e-9)
    assert on.mean() > 0.3 and (np.abs(want[on]) > 1e-6).mean() > 0.5  # real versions
    if plan is path_ops.plan_flip:  # an end's flip has no versions; an obstacle's has
        assert 0 < on.any(axis=1).mean() < 1


@pytest.mark.parametrize("plan", path_ops.PLANS[1:], ids=lambda f: f.__name__)
def test_a_versions_arc_terms_are_the_moved_and_the_flipped_circles_arcs(plan):
    """With the arcs table a version adds ``arc_penalty`` for each of the moved
    obstacle's and the flipped circle's arcs with a violation in the chromosome it makes,
    less the moved obstacle's arc before the move and the flipped circle's after the move
    but unflipped (a plain pass over the chromosomes)."""
    sc, legs = _legs()
    arcs = np.asarray(legs.arcs)
    charge = 0.7 * float(legs.penalty)
    perm, labels = _random(sc.n, 200, seed=6)
    keys = jax.random.split(rng.key(5), len(perm))
    with jax.enable_x64(True):
        def one(k, p, lab):
            pl = plan(k, p, lab, legs)
            plain, made, on, alone = _versions(pl, p, lab, legs)
            scored = _versions(pl, p, lab, legs, arcs=True)[0]
            at = guided.places(pl, p, path_ops.view(p, lab, legs))
            x0, x1 = (jnp.where(at.enters, a, b) for a, b in ((at.p2, at.p), (at.q2, at.q)))
            return scored - plain, on, made, alone, pl, x0, x1
        extra, on, made, alone, plans, *sides = jax.jit(jax.vmap(one))(keys, perm, labels)

    def arc(p, lab, o):
        return arc_violated(arcs, p, lab, o)

    checked = changed = 0
    for i in range(len(perm)):
        moved = perm[i][int(plans.j[i])]
        for s in range(2):
            if not on[i, s]:
                continue
            x = int(sides[s][i])
            mp, ml = made[s][0][i], made[s][1][i]
            ap, al = alone[0][i], alone[1][i]
            want = arc(mp, ml, moved) - arc(perm[i], labels[i], moved)
            if 0 < x < sc.n + 1:  # the flipped obstacle's own arc
                o = perm[i][x - 1]
                want += arc(mp, ml, o) - arc(ap, al, o)
            assert extra[i, s] == pytest.approx(charge * want, abs=1e-9), (i, s)
            checked += 1
            changed += want != 0
    assert checked > 100 and changed > 10


def test_the_move_keeps_the_version_with_the_smallest_leg_score():
    """Of the ten candidates and their twenty versions, the move makes one whose leg
    score is the smallest (float32, to rounding); it is never worse than the guided
    move's choice from the same words."""
    sc, legs = _legs(np.float32)
    perm, labels = _random(sc.n, 40, seed=8)
    words = np.random.default_rng(9).integers(0, 2**32, (40, guided.WORDS),
                                              dtype=np.uint64).astype(np.uint32)

    @jax.jit
    @jax.vmap
    def both(w, p, lab):
        mine = guided_pairs.guided_pairs_one(w, p, lab, legs)
        theirs = guided.guided_one(w, p, lab, legs)
        stacked = guided.candidates(w, p, lab, legs)[0]
        made = []
        for c in range(stacked.j.shape[0]):
            plan = Plan(*(f[c] for f in stacked))
            made.append(guided.leg_score(*path_ops.apply(p, lab, plan), legs))
            _, versions, on, _ = _versions(plan, p, lab, legs)
            made.extend(jnp.where(on[k], guided.leg_score(*m, legs), jnp.inf)
                        for k, m in enumerate(versions))
        return (guided.leg_score(*mine, legs), guided.leg_score(*theirs, legs),
                jnp.stack(made))

    mine, theirs, every = (np.asarray(x) for x in both(words, perm, labels))
    np.testing.assert_allclose(mine, every.min(axis=1), rtol=0, atol=1e-4)
    assert (mine <= theirs + 1e-4).all() and (mine < theirs - 1e-4).sum() >= 3


def test_the_population_form_matches_and_a_reversing_car_takes_the_guided_move():
    """The GA's form moves each chromosome as the one-chromosome move does; with legs
    whose ends are the end move's (a reversing car) the move is the guided move."""
    sc, legs = _legs(np.float32)
    perm, labels = _random(sc.n, 64, seed=11)
    words = np.random.default_rng(4).integers(0, 2**32, (64, guided.WORDS),
                                              dtype=np.uint64).astype(np.uint32)
    got = jax.jit(guided_pairs.guided_pairs_from_words)(words, perm, labels, legs)
    want = jax.jit(jax.vmap(lambda w, p, lab: guided_pairs.guided_pairs_one(w, p, lab, legs)))(
        words, perm, labels)
    for a, b in zip(got, want):
        np.testing.assert_array_equal(a, b)
    plain = jax.jit(guided.guided_from_words)(words, perm, labels, legs)
    assert (np.asarray(got[1]) != np.asarray(plain[1])).any()  # versions were taken
    ends = legs._replace(ends=np.asarray(True))
    got = jax.jit(guided_pairs.guided_pairs_from_words)(words, perm, labels, ends)
    for a, b in zip(got, jax.jit(guided.guided_from_words)(words, perm, labels, ends)):
        np.testing.assert_array_equal(a, b)


def test_the_ga_reads_the_guided_moves_words():
    from hga_jax.search.settings import RECOMMENDED

    op = registry.entry("path_mutation", "guided_pairs")
    assert op.rows(9, RECOMMENDED) == guided_pairs.WORDS == guided.WORDS == 26


def test_the_pairs_start_beyond_pairs_from_obstacles():
    """``pairs_from``: on fewer obstacles ``guided_pairs`` resolves to the guided move
    (the recommended preset: up to 9 obstacles, where it bought nothing measurable),
    from there on it stays; resolving again changes nothing; 0 keeps it everywhere."""
    import dataclasses

    from hga_jax.errors import ConfigError
    from hga_jax.search.settings import PAPER, RECOMMENDED, GASettings

    assert RECOMMENDED.path_mutation == "guided_pairs" and RECOMMENDED.pairs_from == 10
    for n, want in ((0, "guided"), (9, "guided"), (10, "guided_pairs"), (40, "guided_pairs")):
        s = RECOMMENDED.for_obstacles(n)
        assert s.path_mutation == want and s.for_obstacles(n) == s
        assert s.generations == RECOMMENDED.generations + 24 * max(0, n - 9)
    assert RECOMMENDED.for_obstacles(9).pairs_from == 0
    always = dataclasses.replace(RECOMMENDED, pairs_from=0)
    assert always.for_obstacles(5).path_mutation == "guided_pairs"
    assert PAPER.for_obstacles(5).path_mutation == "none"
    with pytest.raises(ConfigError, match=r"ga\.pairs_from: must be >= 0"):
        GASettings.from_mapping({"pairs_from": -1}, "x.toml", prefix="ga")
