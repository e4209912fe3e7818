"""The guided path move (hga_jax/search/guided.py): its leg score against a plain-Python
sum over the float64 tangent table and the decoder's start and goal arcs, and against
the float64 path's lines and end arcs, the change a plan
makes to it against the scores before and after, and the choice of the best-scored
candidate."""
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.host.config import load_scenario
from hga_jax.model.exact import solve
from hga_jax.model.path import _Locator, decode64, evaluate_path, from_chromosome
from hga_jax.search import guided, path_ops, rng

SCENES = ("configs/scenarios/robocup_paper.toml", "configs/scenarios/cluttered.toml")


def _random(n, count, seed):
    r = np.random.default_rng(seed)
    perm = np.stack([r.permutation(n) for _ in range(count)]).astype(np.int32)
    labels = (r.integers(-1, 2, size=(count, n + 2)) * (r.random((count, n + 2)) < 0.4))
    labels[:, 0], labels[:, -1] = r.choice([-1, 1], count), r.choice([-1, 1], count)
    return perm, labels.astype(np.int32)


def _circle(position_label, obstacle=None, end=None):
    """Oriented circle id (hga_jax/model/tangents.py numbering) of a label."""
    side = (1 + position_label) // 2
    if end == "start":
        return side
    if end == "goal":
        return 2 + side
    return 4 + 2 * obstacle + (1 - side)


def _end_arcs(sc, perm, labels):
    """``(length, violations)`` of the decoded path's start arc and of its goal arc."""
    d = jax.tree.map(lambda a: a[0], decode64(sc, perm, labels))
    locate, last = _Locator(sc, "full"), int(d.count) - 1
    out = []
    for s in (0, last):
        circle = tuple(float(v) for v in d.circles[s])
        arc = tuple(float(v) for v in d.arcs[s])
        out.append((circle[2] * arc[4], len(locate.arc(circle, -1, arc, None))))
    return out


def _score_by_hand(sc, perm, labels):
    """Sum over the legs of the touched sequence, from the float64 tangent table, the
    first leg with the decoded start arc and the last with the goal arc."""
    tb = sc.arrays(np.float64).tangents
    seq = [_circle(labels[0], end="start")]
    seq += [_circle(lab, obstacle=o) for o, lab in zip(perm, labels[1:-1]) if lab != 0]
    seq.append(_circle(labels[-1], end="goal"))
    (start_len, start_vio), (goal_len, goal_vio) = _end_arcs(sc, perm, labels)
    legs = list(zip(seq, seq[1:]))
    length = sum(float(tb.length[a, c]) for a, c in legs) + start_len + goal_len
    bad = [int(tb.violations_full[a, c] > 0) for a, c in legs]
    bad[0] |= start_vio > 0
    bad[-1] |= goal_vio > 0
    return length, sum(bad)


@pytest.mark.parametrize("path", SCENES)
def test_leg_score_is_the_summed_tangents_plus_a_penalty_per_bad_leg(path):
    sc = load_scenario(path)
    legs = sc.search_arrays(np.float64, with_legs=True).legs
    perm, labels = _random(sc.n, 60, seed=sc.n)
    opt = solve(sc)  # a path whose legs are all clear
    p0, l0 = from_chromosome(opt.upper, opt.lower, sc.n)
    perm = np.concatenate([perm, np.asarray(p0, np.int32)[None]])
    labels = np.concatenate([labels, np.asarray(l0, np.int32)[None]])
    with jax.enable_x64(True):
        got = np.asarray(jax.jit(jax.vmap(lambda p, lab: guided.leg_score(p, lab, legs)))(
            perm, labels))
    clear = 0
    for i in range(len(perm)):
        length, bad = _score_by_hand(sc, perm[i], labels[i])
        assert got[i] == pytest.approx(length + bad * sc.delta, rel=1e-12, abs=1e-12)
        if bad == 0:  # then the score is the path's lines and end arcs: its length
            clear += 1  # without the arcs on obstacles
            p = evaluate_path(sc, perm[i], labels[i])
            pieces = p.segments
            ends = [x for x in (pieces[0], pieces[-1]) if x["type"] == "arc"]
            lines = sum(np.hypot(*np.subtract(s["end"], s["start"])) for s in pieces
                        if s["type"] == "line")
            arcs = sum(s["radius"] * abs(s["sweep"]) for s in ends)
            assert got[i] == pytest.approx(lines + arcs, rel=1e-9, abs=1e-9)
    assert clear >= 1  # the comparison with the path was made


def test_guided_keeps_the_candidate_with_the_smallest_leg_score():
    sc = load_scenario(SCENES[1])
    legs = sc.search_arrays(np.float32, with_legs=True).legs
    perm, labels = _random(sc.n, 30, seed=3)
    keys = jax.random.split(rng.key(5), len(perm))
    out_p, out_l = jax.jit(jax.vmap(lambda k, p, lab: guided.guided(k, p, lab, legs)))(
        keys, perm, labels)

    @jax.jit
    def candidates(key, p, lab):  # each candidate from its own words, in the documented order
        w, made, at = path_ops._words(key, guided.WORDS), [], 0
        for plan, count in path_ops.PLAN_WORDS:
            for _ in range(guided.PER_MOVE):
                made.append(path_ops.apply(p, lab, plan(w[at:at + count], p, lab, legs)))
                at += count
        assert at == guided.WORDS
        return made, jnp.stack([guided.leg_score(*m, legs) for m in made])

    differs = 0
    for i in range(len(perm)):
        cands, scores = candidates(keys[i], perm[i], labels[i])
        scores = np.asarray(scores)
        best = int(np.argmin(scores))
        made = [j for j, c in enumerate(cands)
                if np.array_equal(out_p[i], c[0]) and np.array_equal(out_l[i], c[1])]
        # the chosen candidate, or one scoring the same to float32 rounding (the change
        # and the whole score are summed differently)
        assert best in made or (made and scores[made[0]] <= scores[best] + 1e-5), i
        differs += len(set(np.round(scores, 5))) > 1
    assert differs > len(perm) // 2  # the candidates differ, so the choice is a real one


def test_the_ga_reads_as_many_words_as_the_guided_move_takes():
    from hga_jax.search import registry
    from hga_jax.search.settings import RECOMMENDED

    op = registry.entry("path_mutation", "guided")
    assert op.rows(9, RECOMMENDED) == guided.WORDS == 26


@pytest.mark.parametrize("shape", [(10,), (10, 2000), (3, 7, 5)])
def test_first_min_is_argmin_taking_the_first_of_equals(shape):
    # few distinct values, so most columns hold ties; the first of equals must win
    x = np.random.default_rng(3).integers(0, 3, shape).astype(np.float32)
    x[..., :1] = 2.0  # and some columns whose minimum comes late
    got = np.asarray(jax.jit(guided.first_min)(jnp.asarray(x)))
    np.testing.assert_array_equal(got, np.argmin(x, axis=0))
    assert got.dtype == np.int32


@pytest.mark.parametrize("plan", path_ops.PLANS, ids=lambda f: f.__name__)
@pytest.mark.parametrize("path", SCENES[1:])
def test_the_change_of_a_plan_is_the_change_of_the_leg_score(plan, path):
    """Scored by the legs it removes and adds, a plan changes the leg score by exactly
    what the chromosome it makes scores more (float64); the move is its plan made."""
    sc = load_scenario(path)
    legs = sc.search_arrays(np.float64, with_legs=True).legs
    legs = legs._replace(penalty=legs.penalty * 10)
    perm, labels = _random(sc.n, 300, seed=7)
    keys = jax.random.split(rng.key(2), len(perm))
    move = getattr(path_ops, plan.__name__.removeprefix("plan_"))
    with jax.enable_x64(True):
        def one(k, p, lab):
            pl = plan(k, p, lab, legs)
            made = path_ops.apply(p, lab, pl)
            return (guided.change(pl, p, lab, path_ops.view(p, lab, legs), guided.weights(legs)),
                    guided.leg_score(p, lab, legs), guided.leg_score(*made, legs), made,
                    move(k, p, lab, legs))
        d, before, after, made, moved = jax.jit(jax.vmap(one))(keys, perm, labels)
    np.testing.assert_allclose(d, np.asarray(after) - np.asarray(before), rtol=0, atol=1e-9)
    for a, b in zip(made, moved):
        np.testing.assert_array_equal(a, b)
    assert (np.asarray(d) != 0).mean() > 0.2  # real changes, not only no-ops


@pytest.mark.parametrize("path", SCENES[1:] + ("configs/scenarios/overlapping.toml",))
def test_the_population_form_moves_each_chromosome_as_it_moves_alone(path):
    """The GA's form lays a population out after the positions (the running counts and
    neighbours made across it); each chromosome ends exactly as the one-chromosome move
    and wrap make it, vmapped (and so as it did before the layout changed)."""
    sc = load_scenario(path)
    legs = sc.search_arrays(np.float32, with_legs=True).legs
    perm, labels = _random(sc.n, 64, seed=11)
    r = np.random.default_rng(4)
    words = r.integers(0, 2**32, (64, guided.WORDS), dtype=np.uint64).astype(np.uint32)
    w3 = r.integers(0, 2**32, (64, 3 * sc.n), dtype=np.uint64).astype(np.uint32)
    via = np.arange(64) % 2 == 1

    @jax.jit
    def population(w, w3, p, lab, v):
        moved = guided.guided_from_words(w, p, lab, legs)
        wp, wl = path_ops.wrap_from_words(w3.T, p.T, lab.T, legs, v)
        return (*moved, wp.T, wl.T)

    @jax.jit
    @jax.vmap
    def alone(w, w3, p, lab, v):
        return (*guided.guided_one(w, p, lab, legs), *path_ops.wrap_from_words(w3, p, lab, legs, v))

    got, want = population(words, w3, perm, labels, via), alone(words, w3, perm, labels, via)
    for a, b in zip(got, want):
        np.testing.assert_array_equal(a, b)
    assert (np.asarray(got[1]) != labels).any()  # the moves did something
    assert (np.asarray(got[3]) != labels).any()  # and so did the wraps


def arc_violated(arcs, p, lab, o):
    """1 where obstacle ``o`` is touched by the chromosome ``(p, lab)`` and its arc (between
    its touched neighbours) has a violation of its own in the turn table ``arcs``."""
    ids, touched = (np.asarray(x) for x in path_ops.path_circles(jnp.asarray(p),
                                                                 jnp.asarray(lab)))
    at = int(np.flatnonzero(np.asarray(p) == o)[0]) + 1
    on = list(np.flatnonzero(touched))
    if at not in on:
        return 0
    k = on.index(at)
    return int(arcs[ids[on[k - 1]], ids[at], ids[on[k + 1]]])


@pytest.mark.parametrize("plan", path_ops.PLANS, ids=lambda f: f.__name__)
def test_the_arc_term_is_the_moved_obstacles_arc_where_it_leaves_and_enters(plan):
    """``guided_arcs``: with the arcs table a plan's change gains ``arc_penalty`` where the
    moved obstacle's arc at its new place (between its touched neighbours in the
    chromosome the plan makes) has a violation of its own, and loses it where its arc at
    the old place had one (found here by a plain pass over both chromosomes); an end's
    flip moves no obstacle and adds nothing; without the table the change is the legs'."""
    sc = load_scenario("configs/scenarios/overlapping.toml")
    legs = sc.search_arrays(np.float64, with_legs=True).legs
    arcs = np.asarray(legs.arcs)
    assert arcs.shape == (sc.n * 2 + 4,) * 3 and 0 < arcs.mean() < 1
    perm, labels = _random(sc.n, 300, seed=5)
    keys = jax.random.split(rng.key(3), len(perm))
    charge = 0.7 * float(legs.penalty)
    with jax.enable_x64(True):
        def one(k, p, lab):
            pl = plan(k, p, lab, legs)
            v, w = path_ops.view(p, lab, legs), guided.weights(legs)
            return (guided.change(pl, p, lab, v, w),
                    guided.change(pl, p, lab, v, w, legs.arcs, charge),
                    pl, path_ops.apply(p, lab, pl))
        plain, scored, plans, (mp, ml) = jax.jit(jax.vmap(one))(keys, perm, labels)

    def arc(p, lab, o):
        return arc_violated(arcs, p, lab, o)

    extra = np.asarray(scored) - np.asarray(plain)
    ends = np.asarray(plans.end) >= 0
    want = [0.0 if ends[i] else charge * (arc(mp[i], ml[i], perm[i][int(plans.j[i])])
                                          - arc(perm[i], labels[i], perm[i][int(plans.j[i])]))
            for i in range(len(perm))]
    np.testing.assert_allclose(extra, want, rtol=0, atol=1e-9)
    if plan is not path_ops.plan_flip:
        assert (np.asarray(want) != 0).mean() > 0.05  # the arcs do change the score
