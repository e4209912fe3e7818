"""Moves on the touched sequence (hga_jax/path_ops.py) and the per-leg blockers they
read (hga_jax/legs.py): worked examples, and invariants of every registered move."""
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax import legs as legs_mod
from hga_jax import path_ops, rng
from hga_jax.config import load_scenario, scenario_from_dict
from hga_jax.errors import ConfigError
from hga_jax.settings import GASettings


def _scene(obstacles, start=(0.0, 0.0, 0.0), goal=(3.0, 0.0, 0.0)):
    return scenario_from_dict({
        "name": "line", "robot": {"radius": 0.09, "min_turn_radius": 0.18},
        "start": {"x": start[0], "y": start[1], "heading_deg": start[2]},
        "goal": {"x": goal[0], "y": goal[1], "heading_deg": goal[2]},
        "obstacles": [{"x": x, "y": y} for x, y in obstacles]})


def _touched(perm, labels):
    """The touched sequence: (obstacle, label) in permutation order."""
    return [(int(o), int(l)) for o, l in zip(perm, labels[1:-1]) if l != 0]


def _random(n, count, seed):
    r = np.random.default_rng(seed)
    perm = np.stack([r.permutation(n) for _ in range(count)]).astype(np.int32)
    labels = r.integers(-1, 2, size=(count, n + 2)).astype(np.int32)
    labels[:, 0] = r.choice([-1, 1], count)
    labels[:, -1] = r.choice([-1, 1], count)
    labels[: count // 8, 1:-1] = 0  # some with nothing touched
    labels[count // 8: count // 4, 1:-1] = r.choice([-1, 1], (count // 4 - count // 8, n))
    return perm, labels


# --- move_apply: worked examples -------------------------------------------------

def test_move_forwards_backwards_and_in_place():
    perm = jnp.array([4, 0, 3, 1, 2], jnp.int32)
    lab = jnp.array([1, -1, 0, 1, 0, -1, -1], jnp.int32)  # ends 1 and -1
    p, l = path_ops.move_apply(perm, lab, jnp.int32(1), jnp.int32(3), jnp.int32(1))
    assert p.tolist() == [4, 3, 1, 0, 2]  # obstacle 0 from position 1 to 3
    assert l.tolist() == [1, -1, 1, 0, 1, -1, -1]  # its label now +1; the others travel
    p, l = path_ops.move_apply(perm, lab, jnp.int32(4), jnp.int32(0), jnp.int32(-1))
    assert p.tolist() == [2, 4, 0, 3, 1] and l.tolist() == [1, -1, -1, 0, 1, 0, -1]
    p, l = path_ops.move_apply(perm, lab, jnp.int32(2), jnp.int32(2), jnp.int32(-1))
    assert p.tolist() == perm.tolist() and l.tolist() == [1, -1, 0, -1, 0, -1, -1]


# --- every registered move: invariants --------------------------------------------

@pytest.fixture(scope="module")
def scenes():
    out = {1: _scene([(1.5, 0.0)]), 9: load_scenario("configs/scenarios/robocup_paper.toml"),
           28: load_scenario("configs/scenarios/cluttered.toml")}  # n > 20: gathers
    return {n: (sc, sc.search_arrays(np.float64, "full", with_legs=True).legs)
            for n, sc in out.items()}


@pytest.mark.parametrize("n", [1, 9, 28])
@pytest.mark.parametrize("name", sorted(path_ops.MOVES))
def test_every_move_keeps_chromosomes_valid_and_does_what_it_says(scenes, name, n):
    sc, legs = scenes[n]
    assert sc.n == n
    count = 200
    perm, labels = _random(n, count, seed=n)
    keys = jax.random.split(rng.key(11), count)
    move = path_ops.MOVES[name]
    p2, l2 = jax.jit(jax.vmap(lambda k, p, l: move(k, p, l, legs)))(keys, perm, labels)
    p2, l2 = np.asarray(p2), np.asarray(l2)
    assert np.array_equal(np.sort(p2, axis=1), np.tile(np.arange(n), (count, 1)))
    assert np.all(np.isin(l2, (-1, 0, 1))) and np.all(l2[:, [0, -1]] != 0)
    changed = 0
    for i in range(count):
        before, after = _touched(perm[i], labels[i]), _touched(p2[i], l2[i])
        ends_before, ends_after = labels[i, [0, -1]], l2[i, [0, -1]]
        changed += (before != after) or not np.array_equal(ends_before, ends_after)
        if name == "flip":  # exactly one touched circle reversed, nothing else
            assert np.array_equal(p2[i], perm[i])
            diff = np.flatnonzero(l2[i] != labels[i])
            assert diff.size == 1 and l2[i, diff[0]] == -labels[i, diff[0]] != 0
        elif name == "drop":
            assert np.array_equal(p2[i], perm[i]) and np.array_equal(ends_after, ends_before)
            if before:
                assert len(after) == len(before) - 1 and all(t in before for t in after)
                assert [t for t in before if t in after] == after
            else:
                assert after == before
        elif name == "insert":
            assert np.array_equal(ends_after, ends_before)
            if len(before) < n:
                assert len(after) == len(before) + 1
                assert [t for t in after if t in before] == before  # order and labels kept
            else:
                assert after == before
        elif name == "shift":
            assert np.array_equal(ends_after, ends_before)
            assert sorted(after) == sorted(before)
        elif name == "repair":
            assert np.array_equal(ends_after, ends_before)
            assert len(after) in (len(before), len(before) + 1)
    if n > 1:  # the moves move (at n = 1 most have nothing to act on)
        assert changed > count // 5, changed


def test_repair_wraps_a_blocking_obstacle_between_the_legs_circles(scenes):
    """Worked example: the straight start-goal path runs through obstacle 0 at
    (1.5, 0); the direct chromosome's only leg is blocked by it, so repair touches
    it, in either direction, in both cases between the start and the goal."""
    sc, legs = _scene([(1.5, 0.0), (1.5, 1.5)]), None
    legs = sc.search_arrays(np.float64, "full", with_legs=True).legs
    perm = jnp.array([1, 0], jnp.int32)
    lab = jnp.array([1, 0, 0, -1], jnp.int32)  # start CW, goal CCW: the leg crosses (1.5, 0)
    ids, nxt, blocked = path_ops.blocked_legs(perm, lab, legs)
    assert blocked.tolist() == [True, False, False, False]
    labels = set()
    for s in range(40):
        p, l = path_ops.repair(rng.key(s), perm, lab, legs)
        assert _touched(p, l)[0][0] == 0 and len(_touched(p, l)) == 1
        labels.add(_touched(p, l)[0][1])
        ids, nxt, blocked = path_ops.blocked_legs(p, l, legs)
    assert labels == {-1, 1}


def test_wrap_blockers_leaves_no_blocked_leg_or_uses_n_steps():
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    legs = sc.search_arrays(np.float64, "full", with_legs=True).legs
    perm, labels = _random(sc.n, 100, seed=5)
    keys = jax.random.split(rng.key(3), 100)
    p2, l2 = jax.jit(jax.vmap(lambda k, p, l: path_ops.wrap_blockers(k, p, l, legs)))(
        keys, perm, labels)
    for i in range(100):
        assert np.array_equal(np.asarray(l2[i, [0, -1]]), labels[i, [0, -1]])  # ends kept
        _, _, blocked = path_ops.blocked_legs(p2[i], l2[i], legs)
        touched = np.count_nonzero(np.asarray(l2[i, 1:-1]))
        assert touched >= 1  # every direct path of this scene is blocked
        assert not np.any(np.asarray(blocked)) or touched == sc.n


def test_wrap_blockers_leaves_a_clear_direct_path_alone():
    sc = _scene([(1.5, 2.0)])  # far off the straight line
    legs = sc.search_arrays(np.float64, "full", with_legs=True).legs
    perm, lab = jnp.array([0], jnp.int32), jnp.array([1, 1, -1], jnp.int32)
    p, l = path_ops.wrap_blockers(rng.key(0), perm, lab, legs)
    assert l.tolist() == [1, 0, -1]  # the obstacle label is cleared, nothing wrapped


# --- legs: an independent check ----------------------------------------------------

def test_blockers_match_a_point_segment_distance_check():
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    sa = sc.search_arrays(np.float64, "full", with_legs=True)
    tb, L = sa.tangents, sa.legs
    p1 = np.stack([tb.p1x, tb.p1y], -1)[:, :, None, :]
    p2 = np.stack([tb.p2x, tb.p2y], -1)[:, :, None, :]
    q = np.asarray(sc.centres)[None, None]
    d = p2 - p1
    t = np.clip(np.sum((q - p1) * d, -1) / np.maximum(np.sum(d * d, -1), 1e-300), 0, 1)
    dist = np.linalg.norm(p1 + t[..., None] * d - q, axis=-1)
    expect = dist < np.asarray(sc.model_radii)[None, None] - 1e-7
    assert np.array_equal(np.asarray(L.blockers), expect)
    assert np.array_equal(np.asarray(L.blocked), expect.any(-1))
    assert 0 < expect.mean() < 0.5  # a real mix of clear and blocked legs


def test_legs_are_built_once_per_scenario_and_only_on_request():
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    assert sc.search_arrays().legs is None
    a = sc.search_arrays(with_legs=True).legs
    assert a is sc.search_arrays(np.float64, "full", with_legs=True).legs
    assert isinstance(a, legs_mod.Legs) and a.blockers.shape == (22, 22, 9)


# --- settings --------------------------------------------------------------------

@pytest.mark.parametrize("key, value, message", [
    ("path_mutation", "nope", "ga.path_mutation: must be one of none, flip"),
    ("restart_after", -1, "ga.restart_after: must be >= 0"),
    ("seeding", 1.5, "ga.seeding: must be a probability in"),
    ("pm_path", float("nan"), "ga.pm_path: must be a probability in"),
])
def test_bad_path_settings_are_refused(key, value, message):
    with pytest.raises(ConfigError, match=message):
        GASettings.from_mapping({key: value}, "x.toml")


def test_uses_legs():
    assert not GASettings().uses_legs
    assert GASettings(path_mutation="flip").uses_legs and GASettings(seeding=0.5).uses_legs
    assert not GASettings(restart_after=4).uses_legs


def test_register_move():
    def keep(key, perm, labels, legs):
        return perm, labels

    path_ops.register_move("keep_for_test", keep)
    try:
        assert GASettings(path_mutation="keep_for_test").path_mutation == "keep_for_test"
        with pytest.raises(ValueError, match="already registered"):
            path_ops.register_move("keep_for_test", lambda *a: a[1:3])
    finally:
        del path_ops.MOVES["keep_for_test"]
