"""Moves on the touched sequence (hga_jax/search/path_ops.py) and the per-leg blockers they
read (hga_jax/model/legs.py): worked examples, a numpy reference of ``move_apply``, the
invariants of every registered move (n = 1, 9 and 30; n > 20 takes permutation.take's
gathers), ``wrap_blockers`` on hand-built scenes, ``legs.build`` against an
independent point-segment distance, and the path settings."""
import tomllib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.model import circle_ids
from hga_jax.model import legs as legs_mod
from hga_jax.search import path_ops, permutation, registry, rng
from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.errors import ConfigError
from hga_jax.search.settings import GASettings

COUNT = 200  # random chromosomes (and keys) per move and scene


# --- helpers (numpy, written from docs/model.md and the module docs) ---------------

def _scene(obstacles, start=(0.0, 0.0, 0.0), goal=(3.0, 0.0, 0.0), name="hand"):
    """Robot radius 0.09 m, rho 0.18 m: a default obstacle's model radius is 0.18 m.
    ``obstacles``: (x, y) or (x, y, physical radius)."""
    return scenario_from_dict({
        "name": name, "robot": {"radius": 0.09, "min_turn_radius": 0.18},
        "start": {"x": start[0], "y": start[1], "heading_deg": start[2]},
        "goal": {"x": goal[0], "y": goal[1], "heading_deg": goal[2]},
        "obstacles": [{"x": o[0], "y": o[1], **({"radius": o[2]} if len(o) > 2 else {})}
                      for o in obstacles]})


def _grid30():
    """30 obstacles on a jittered 10 x 3 grid across the start-goal line, no two model
    circles overlapping (centres >= 0.4 m apart, model radius 0.18 m)."""
    r = np.random.default_rng(30)
    pts = [(round(0.6 + 0.5 * c + r.uniform(-0.05, 0.05), 3),
            round(-0.6 + 0.6 * row + r.uniform(-0.05, 0.05), 3))
           for c in range(10) for row in range(3)]
    return _scene(pts, goal=(5.6, 0.0, 0.0), name="grid30")


def _cluttered30():
    """configs/scenarios/cluttered.toml (28 obstacles of mixed radii, overlapping model
    circles) plus two more obstacles."""
    with open("configs/scenarios/cluttered.toml", "rb") as f:
        d = tomllib.load(f)
    d["obstacles"] += [{"x": 1.2, "y": 2.0}, {"x": 3.0, "y": 1.6, "radius": 0.12}]
    return scenario_from_dict(d)


def _legs(sc):
    return sc.search_arrays(np.float64, "full", with_legs=True).legs


def _touched(perm, labels):
    """The touched obstacles: (obstacle, label) in permutation order."""
    return [(int(o), int(l)) for o, l in zip(perm, labels[1:-1]) if l != 0]


def test_obstacle_of_inverts_the_circle_ids():
    i = np.repeat(np.arange(7), 2)
    ids = circle_ids.obstacle(i, np.tile([0, 1], 7))
    assert sorted(ids.tolist()) == list(range(circle_ids.POSES, circle_ids.count(7)))
    assert circle_ids.obstacle_of(jnp.asarray(ids)).tolist() == i.tolist()


def _circle_ids(perm, labels):
    """Circle ids (hga_jax/model/tangents.py numbering) of the touched sequence, start to goal."""
    n = len(perm)
    ids = [(1 + int(labels[0])) // 2]
    ids += [4 + 2 * int(perm[p]) + (1 - int(labels[p + 1])) // 2
            for p in range(n) if labels[p + 1] != 0]
    return ids + [2 + (1 + int(labels[-1])) // 2]


def _blocked_pairs(perm, labels, blocked):
    """The consecutive (circle, circle) pairs of the touched sequence whose leg is blocked."""
    ids = _circle_ids(perm, labels)
    return [(a, c) for a, c in zip(ids, ids[1:]) if blocked[a, c]]


def _random(n, count, seed):
    """Random chromosomes: 1/8 with no obstacle touched, 1/8 with all touched."""
    r = np.random.default_rng(seed)
    perm = np.stack([r.permutation(n) for _ in range(count)]).astype(np.int32)
    labels = r.integers(-1, 2, size=(count, n + 2)).astype(np.int32)
    labels[:, 0] = r.choice([-1, 1], count)
    labels[:, -1] = r.choice([-1, 1], count)
    labels[: count // 8, 1:-1] = 0
    labels[count // 8: count // 4, 1:-1] = r.choice([-1, 1], (count // 4 - count // 8, n))
    return perm, labels


def _move_ref(perm, mid, j, i, label):
    """Reference of move_apply on the middle labels: pop position j, put it at i."""
    p, m = list(perm), list(mid)
    o = p.pop(j)
    m.pop(j)
    p.insert(i, o)
    m.insert(i, label)
    return p, m


def _explain(perm, mid, p2, m2):
    """Every (j, i) such that (p2, m2) is (perm, mid) with the obstacle at position j
    moved to i (taking label m2[i]); [] if it is no single move."""
    perm, mid, p2, m2 = (list(map(int, x)) for x in (perm, mid, p2, m2))
    n = len(perm)
    if perm == p2:
        diff = [x for x in range(n) if mid[x] != m2[x]]
        return [] if len(diff) > 1 else [(diff[0], diff[0])] if diff else [(x, x) for x in range(n)]
    d = [x for x in range(n) if perm[x] != p2[x]]
    a, b = d[0], d[-1]
    return [(j, i) for j, i in ((a, b), (b, a)) if _move_ref(perm, mid, j, i, m2[i]) == (p2, m2)]


# --- what each move promises, chromosome by chromosome -----------------------------
# Each takes (perm, labels, p2, l2, legs) as numpy arrays and says whether the move
# could have produced (p2, l2) from (perm, labels).

def _is_flip(perm, lab, p2, l2, legs=None):
    diff = np.flatnonzero(l2 != lab)
    return (np.array_equal(p2, perm) and diff.size == 1
            and lab[diff[0]] != 0 and l2[diff[0]] == -lab[diff[0]])


def _is_drop(perm, lab, p2, l2, legs=None):
    if not np.array_equal(p2, perm):
        return False
    if not np.any(lab[1:-1]):
        return np.array_equal(l2, lab)
    diff = np.flatnonzero(l2 != lab)
    return diff.size == 1 and 1 <= diff[0] <= len(perm) and lab[diff[0]] != 0 and l2[diff[0]] == 0


def _is_insert(perm, lab, p2, l2, legs=None):
    if not np.array_equal(l2[[0, -1]], lab[[0, -1]]):
        return False
    if np.all(lab[1:-1] != 0):  # nothing to insert
        return np.array_equal(p2, perm) and np.array_equal(l2, lab)
    before, after = _touched(perm, lab), _touched(p2, l2)
    ok = any(lab[1 + j] == 0 and l2[1 + i] != 0 for j, i in _explain(perm, lab[1:-1], p2, l2[1:-1]))
    # so one more obstacle is touched, the others in their order with their labels
    assert not ok or (len(after) == len(before) + 1 and [t for t in after if t in before] == before)
    return ok


def _is_shift(perm, lab, p2, l2, legs=None):
    if not np.array_equal(l2[[0, -1]], lab[[0, -1]]):
        return False
    if not np.any(lab[1:-1]):  # nothing to shift
        return np.array_equal(p2, perm) and np.array_equal(l2, lab)
    ok = any(lab[1 + j] != 0 and l2[1 + i] == lab[1 + j]
             for j, i in _explain(perm, lab[1:-1], p2, l2[1:-1]))
    assert not ok or sorted(_touched(p2, l2)) == sorted(_touched(perm, lab))
    return ok


def _repair_kind(perm, lab, p2, l2, legs):
    """"wrap": an obstacle that blocks a blocked leg moved, in either direction, to just
    after the leg's first circle (so between the leg's two circles); "insert": an
    insert, allowed when no leg is blocked or when the drawn blocker is the leg's first
    circle (a missing tangent's stand-in can cross its own circles); None: neither."""
    n = len(perm)
    if not np.array_equal(l2[[0, -1]], lab[[0, -1]]):
        return None
    blockers, blocked = np.asarray(legs.blockers), np.asarray(legs.blocked)
    pos = [0] + [p + 1 for p in range(n) if lab[p + 1] != 0] + [n + 1]  # label positions
    ids = _circle_ids(perm, lab)
    legs_in = [(k, ids[t], ids[t + 1]) for t, k in enumerate(pos[:-1])
               if blocked[ids[t], ids[t + 1]]]  # (first label position, a, c)
    for j, i in _explain(perm, lab[1:-1], p2, l2[1:-1]):
        o = int(perm[j])
        if l2[1 + i] == 0:
            continue
        for k, a, c in legs_in:
            q = k - 1  # the leg's first circle as a permutation position (-1: start)
            if blockers[a, c, o] and j != q and i == (q + 1 if j > q else q):
                return "wrap"
    first_is_blocker = any(k >= 1 and blockers[a, c, int(perm[k - 1])] for k, a, c in legs_in)
    if (not legs_in or first_is_blocker) and _is_insert(perm, lab, p2, l2):
        return "insert"
    return None


def _is_repair(perm, lab, p2, l2, legs):
    return _repair_kind(perm, lab, p2, l2, legs) is not None


CHECKS = {"flip": _is_flip, "drop": _is_drop, "insert": _is_insert, "shift": _is_shift,
          "repair": _is_repair}


# --- the helpers themselves --------------------------------------------------------

def test_explain_finds_single_moves_only():
    perm, mid = [4, 0, 3, 1, 2], [-1, 0, 1, 0, -1]
    p2, m2 = _move_ref(perm, mid, 1, 3, 1)
    assert (p2, m2) == ([4, 3, 1, 0, 2], [-1, 1, 0, 1, -1])
    assert _explain(perm, mid, p2, m2) == [(1, 3)]
    assert _explain(perm, mid, [0, 4, 3, 1, 2], [0, -1, 1, 0, -1]) == [(0, 1), (1, 0)]
    assert _explain(perm, mid, [4, 0, 2, 1, 3], mid) == []  # a swap of distant elements
    assert _explain(perm, mid, perm, [-1, 0, 1, 1, 1]) == []  # two labels changed


# --- move_apply: worked examples and the reference -----------------------------------

def test_move_forwards_backwards_and_in_place():
    perm = jnp.array([4, 0, 3, 1, 2], jnp.int32)
    lab = jnp.array([1, -1, 0, 1, 0, -1, -1], jnp.int32)  # start +1, goal -1
    # forwards: obstacle 0 from position 1 to 3; 3 and 1 shift back with their labels
    p, l = path_ops.move_apply(perm, lab, jnp.int32(1), jnp.int32(3), jnp.int32(1))
    assert p.tolist() == [4, 3, 1, 0, 2]
    assert l.tolist() == [1, -1, 1, 0, 1, -1, -1]
    # backwards: obstacle 2 from the last position to the first, label -1
    p, l = path_ops.move_apply(perm, lab, jnp.int32(4), jnp.int32(0), jnp.int32(-1))
    assert p.tolist() == [2, 4, 0, 3, 1]
    assert l.tolist() == [1, -1, -1, 0, 1, 0, -1]
    # in place: only the label changes
    p, l = path_ops.move_apply(perm, lab, jnp.int32(2), jnp.int32(2), jnp.int32(-1))
    assert p.tolist() == [4, 0, 3, 1, 2] and l.tolist() == [1, -1, 0, -1, 0, -1, -1]
    # one step forwards = a swap of neighbours, labels swapped with them
    p, l = path_ops.move_apply(perm, lab, jnp.int32(0), jnp.int32(1), jnp.int32(-1))
    assert p.tolist() == [0, 4, 3, 1, 2] and l.tolist() == [1, 0, -1, 1, 0, -1, -1]


def test_move_leaves_start_and_goal_labels_alone():
    perm = jnp.array([1, 0], jnp.int32)
    for ends in ([1, 1], [1, -1], [-1, 1], [-1, -1]):
        lab = jnp.array([ends[0], 1, 0, ends[1]], jnp.int32)
        p, l = path_ops.move_apply(perm, lab, jnp.int32(0), jnp.int32(1), jnp.int32(-1))
        assert p.tolist() == [0, 1] and l.tolist() == [ends[0], 0, -1, ends[1]]
    p, l = path_ops.move_apply(jnp.array([0], jnp.int32), jnp.array([-1, 0, 1], jnp.int32),
                               jnp.int32(0), jnp.int32(0), jnp.int32(1))
    assert p.tolist() == [0] and l.tolist() == [-1, 1, 1]


@pytest.mark.parametrize("n", [1, 2, 7, 30])
def test_move_apply_matches_the_reference_for_every_pair(n):
    """Every (j, i) at once, vmapped and jitted (n = 30 takes the gathers)."""
    perm, labels = _random(n, 1, seed=100 + n)
    perm, labels = perm[0], labels[0]
    labels[1:-1] = np.random.default_rng(n).choice([-1, 1], n) * (np.arange(n) % 3 != 0)
    j, i = (x.ravel().astype(np.int32) for x in np.meshgrid(np.arange(n), np.arange(n)))
    new = np.where(np.arange(j.size) % 2 == 0, 1, -1).astype(np.int32)
    p2, l2 = jax.jit(jax.vmap(path_ops.move_apply, (None, None, 0, 0, 0)))(perm, labels, j, i, new)
    p2, l2 = np.asarray(p2), np.asarray(l2)
    for t in range(j.size):
        rp, rm = _move_ref(perm, labels[1:-1], j[t], i[t], new[t])
        assert p2[t].tolist() == rp and l2[t, 1:-1].tolist() == rm, (j[t], i[t])
        assert l2[t, 0] == labels[0] and l2[t, -1] == labels[-1]


# --- every registered move: invariants over random chromosomes and keys --------------

SCENES = {"one": (1, lambda: _scene([(1.5, 0.0)])),
          "robocup": (9, lambda: load_scenario("configs/scenarios/robocup_paper.toml")),
          "grid30": (30, _grid30),
          "cluttered30": (30, _cluttered30)}


@pytest.fixture(scope="module")
def scenes():
    return {name: (lambda sc: (sc, _legs(sc)))(make()) for name, (_, make) in SCENES.items()}


def _run(move, legs, perm, labels, seed):
    keys = jax.random.split(rng.key(seed), len(perm))
    p2, l2 = jax.jit(jax.vmap(lambda k, p, l: move(k, p, l, legs)))(keys, perm, labels)
    return np.asarray(p2), np.asarray(l2)


def test_registry_holds_the_documented_moves():
    assert set(registry.names("path_mutation")) >= {"none", "flip", "drop", "insert", "shift",
                                                     "repair", "mixed", "guided",
                                                     "guided_pairs"}


@pytest.mark.parametrize("name, scene", [  # the composite moves on 30 obstacles on demand
    # (-m slow); every move on one and nine obstacles, and the simple ones on 30, by default
    pytest.param(n, s, marks=pytest.mark.slow)
    if n in ("guided", "guided_pairs", "mixed") and SCENES[s][0] == 30 else (n, s)
    for s in SCENES for n in sorted(registry.names("path_mutation")[1:])],
    ids=lambda v: str(v))
def test_every_move_keeps_chromosomes_valid_and_does_what_it_says(scenes, name, scene):
    sc, legs = scenes[scene]
    n = SCENES[scene][0]
    assert sc.n == n
    perm, labels = _random(n, COUNT, seed=n + len(scene))
    p2, l2 = _run(registry.get("path_mutation", name), legs, perm, labels, seed=11)
    assert p2.shape == (COUNT, n) and l2.shape == (COUNT, n + 2)
    assert p2.dtype == np.int32 and l2.dtype == np.int32
    assert np.array_equal(np.sort(p2, axis=1), np.tile(np.arange(n), (COUNT, 1)))
    assert np.all(np.isin(l2, (-1, 0, 1))) and np.all(l2[:, [0, -1]] != 0)
    if name.startswith("guided"):  # the best of candidate moves: each result is one of
        # them (guided_pairs: or one of them with one touched circle then turned)
        def some_move(lab2):
            return any(check(perm[c], labels[c], p2[c], lab2, legs) for check in CHECKS.values())

        turned = 0
        for c in range(COUNT):
            if some_move(l2[c]):
                continue
            assert name == "guided_pairs", (c, perm[c], labels[c], p2[c], l2[c])
            flips = [np.where(np.arange(n + 2) == t, -l2[c], l2[c]) for t in np.flatnonzero(l2[c])]
            assert any(some_move(f) for f in flips), (c, perm[c], labels[c], p2[c], l2[c])
            turned += 1
        if name == "guided_pairs" and n > 1:
            assert turned > 0  # the paired versions are chosen now and then
        return
    if name == "mixed":
        kinds = {nm: 0 for nm in CHECKS}
        for c in range(COUNT):
            ok = [nm for nm, check in CHECKS.items()
                  if check(perm[c], labels[c], p2[c], l2[c], legs)]
            assert ok, (c, perm[c], labels[c], p2[c], l2[c])
            for nm in ok:
                kinds[nm] += 1
        changed = np.sum(np.any(p2 != perm, 1) | np.any(l2 != labels, 1))
        if n > 1:  # each kind of move shows up (a result may fit several), and most move
            assert min(kinds.values()) >= COUNT // 20, kinds
            assert changed > COUNT // 2, changed
        else:  # flips always change something
            assert changed >= COUNT // 10, changed
        return
    assert name in CHECKS, f"no check written for the move {name!r}"
    check = CHECKS[name]
    for c in range(COUNT):
        assert check(perm[c], labels[c], p2[c], l2[c], legs), (c, perm[c], labels[c], p2[c], l2[c])
    if name == "flip":
        return  # _is_flip: exactly one non-zero label reversed, nothing else
    if name == "repair":
        kinds = [_repair_kind(perm[c], labels[c], p2[c], l2[c], legs) for c in range(COUNT)]
        assert kinds.count("wrap") >= COUNT // 5, kinds.count("wrap")
        if n == 1:  # touched: no leg blocked, an insert (a no-op); untouched: a wrap
            assert kinds.count("insert") >= COUNT // 5
            assert all((labels[c, 1] != 0) == (kinds[c] == "insert") for c in range(COUNT))
    # the moves move: every chromosome with something to act on changes (drop, insert)
    # or most do (shift and repair may put an obstacle back where it was)
    changed = np.any(p2 != perm, 1) | np.any(l2 != labels, 1)
    touched = np.count_nonzero(labels[:, 1:-1], axis=1)
    if name == "drop":
        assert np.array_equal(changed, touched > 0)
    elif name == "insert":
        assert np.array_equal(changed, touched < n)
        assert np.array_equal(np.count_nonzero(l2[:, 1:-1], axis=1), np.minimum(touched + 1, n))
    elif name == "shift":
        assert not np.any(changed[touched == 0])
        if n > 1:
            assert changed.sum() > COUNT // 2
    elif name == "repair" and n > 1:
        assert changed.sum() > COUNT // 2


def test_the_checks_can_fail():
    """The predicates above refuse the other moves' results (so they can catch a bug)."""
    perm, lab = np.array([2, 0, 1]), np.array([1, 1, 0, -1, -1])
    flipped = np.array([1, -1, 0, -1, -1])
    dropped = np.array([1, 0, 0, -1, -1])
    assert _is_flip(perm, lab, perm, flipped) and not _is_flip(perm, lab, perm, dropped)
    assert _is_drop(perm, lab, perm, dropped) and not _is_drop(perm, lab, perm, flipped)
    assert not _is_flip(perm, lab, perm, lab) and not _is_drop(perm, lab, perm, lab)
    ins_p, ins_m = _move_ref(perm, lab[1:-1], 1, 0, 1)  # untouched obstacle 0 first, CW
    ins_p, ins = np.array(ins_p), np.array([1, *ins_m, -1])
    assert _is_insert(perm, lab, ins_p, ins) and not _is_shift(perm, lab, ins_p, ins)
    sh_p, sh_m = _move_ref(perm, lab[1:-1], 2, 0, -1)  # touched obstacle 1 first, label kept
    sh_p, sh = np.array(sh_p), np.array([1, *sh_m, -1])
    assert _is_shift(perm, lab, sh_p, sh) and not _is_insert(perm, lab, sh_p, sh)
    assert not _is_shift(perm, lab, sh_p, np.array([1, 1, 1, 0, -1]))  # label changed
    assert not _is_insert(perm, lab, perm, np.array([-1, 1, 0, -1, -1]))  # start changed


# --- repair and wrap_blockers: hand-built scenes ------------------------------------

def _keys_apply(move, count, perm, labels, legs):
    """``move`` on one chromosome under ``count`` keys (vmapped, jitted), as numpy."""
    keys = jax.random.split(rng.key(count), count)
    p, l = jax.jit(jax.vmap(lambda k: move(k, perm, labels, legs)))(keys)
    return np.asarray(p), np.asarray(l)


def test_repair_wraps_a_blocking_obstacle_between_the_legs_circles():
    """The straight start-goal leg runs through obstacle 0 at (1.5, 0); obstacle 1 at
    (1.5, 1.5) is clear of it. repair touches obstacle 0, in either direction, between
    the start and the goal, whatever the permutation."""
    sc = _scene([(1.5, 0.0), (1.5, 1.5)])
    legs = _legs(sc)
    for perm in ([1, 0], [0, 1]):
        perm = jnp.array(perm, jnp.int32)
        lab = jnp.array([1, 0, 0, -1], jnp.int32)  # start CW, goal CCW
        _, _, blocked = path_ops.blocked_legs(perm, lab, legs)
        assert blocked.tolist() == [True, False, False, False]
        assert _blocked_pairs(perm, lab, legs.blocked) == [(1, 2)]
        assert np.flatnonzero(legs.blockers[1, 2]).tolist() == [0]
        seen = set()
        for p, l in zip(*_keys_apply(path_ops.repair, 40, perm, lab, legs)):
            assert _touched(p, l) in ([(0, 1)], [(0, -1)])
            assert l[0] == 1 and l[-1] == -1 and sorted(p.tolist()) == [0, 1]
            assert p.tolist()[0] == 0  # moved to just after the start circle
            seen.add(_touched(p, l)[0][1])
        assert seen == {-1, 1}


def test_repair_wraps_between_the_two_obstacles_of_a_blocked_leg():
    """Start CW, obstacle 0 at (1, 1) CW, obstacle 2 at (3, 1) CW, goal: the leg
    0 -> 2 (along y = 1.18) runs through obstacle 1 at (2, 1.1); repair puts 1 between
    0 and 2 (or inserts nothing else: the other legs are clear)."""
    sc = _scene([(1.0, 1.0), (2.0, 1.1), (3.0, 1.0)], goal=(4.0, 0.0, 0.0))
    legs = _legs(sc)
    perm = jnp.array([1, 0, 2], jnp.int32)  # 1 untouched, before the leg
    lab = jnp.array([1, 0, 1, 1, 1], jnp.int32)
    assert _blocked_pairs(perm, lab, legs.blocked) == [(4, 8)]
    assert np.flatnonzero(legs.blockers[4, 8]).tolist() == [1]
    seen = set()
    for p, l in zip(*_keys_apply(path_ops.repair, 30, perm, lab, legs)):
        assert p.tolist() == [0, 1, 2]
        t = _touched(p, l)
        assert [o for o, _ in t] == [0, 1, 2] and t[0] == (0, 1) and t[2] == (2, 1)
        seen.add(t[1][1])
    assert seen == {-1, 1}


def _line_scene(obstacles):
    """Start (0, 0) heading 0, goal (2, 0) heading 0."""
    return _scene(obstacles, goal=(2.0, 0.0, 0.0), name="line")


def test_wrap_blockers_touches_the_obstacle_on_the_straight_line():
    sc = _line_scene([(1.0, 0.0), (1.0, 2.0)])  # obstacle 1 far off the line
    legs = _legs(sc)
    # every direct leg (each start circle to each goal circle) runs through obstacle 0
    for a in (0, 1):
        for c in (2, 3):
            assert legs.blocked[a, c] and np.flatnonzero(legs.blockers[a, c]).tolist() == [0]
    perm = np.array([[0, 1], [1, 0]] * 8, np.int32)
    ends = np.array([[s, g] for s in (-1, 1) for g in (-1, 1)] * 4, np.int32)
    labels = np.concatenate([ends[:, :1], np.tile([[1, -1]], (16, 1)), ends[:, 1:]], 1)
    keys = jax.random.split(rng.key(5), 16)
    p2, l2 = jax.jit(jax.vmap(lambda k, p, l: path_ops.wrap_blockers(k, p, l, legs)))(
        keys, perm, labels)
    p2, l2 = np.asarray(p2), np.asarray(l2)
    seen = set()
    for c in range(16):
        t = _touched(p2[c], l2[c])
        assert len(t) == 1 and t[0][0] == 0, t  # obstacle 0, nothing else
        seen.add(t[0][1])
        assert np.array_equal(l2[c, [0, -1]], ends[c])
        assert sorted(p2[c]) == [0, 1]
        assert _blocked_pairs(p2[c], l2[c], legs.blocked) == []
    assert seen == {-1, 1}


def test_wrap_blockers_leaves_a_clear_direct_path_alone():
    sc = _line_scene([(1.0, 2.0)])  # far off the straight line
    legs = _legs(sc)
    assert not legs.blocked[:4, :4].any()
    for s, g, mid in ((1, -1, 1), (-1, 1, -1), (1, 1, 0)):
        lab = jnp.array([s, mid, g], jnp.int32)
        p, l = path_ops.wrap_blockers(rng.key(s + 3 * g), jnp.array([0], jnp.int32), lab, legs)
        assert p.tolist() == [0] and l.tolist() == [s, 0, g]  # cleared, nothing wrapped


@pytest.mark.parametrize("make", [lambda: load_scenario("configs/scenarios/robocup_paper.toml"),
                                  _grid30], ids=["robocup", "grid30"])
def test_wrap_blockers_leaves_no_blocked_leg_or_uses_n_steps(make):
    """On these scenes n steps always suffice: no leg between consecutive touched
    circles is blocked (legs.blocked looked up here, not through blocked_legs), unless
    every obstacle is touched. The tangents' own blockers (``legs.build``): the search's
    legs add the end arcs' (``with_end_arcs``), and some of those draws then spend
    their n steps moving touched obstacles to and fro."""
    sc = make()
    sa = sc.search_arrays(np.float64)
    legs, n = legs_mod.build(sa.tangents, sa.centres, sa.model_radii), sc.n
    perm, labels = _random(n, 100, seed=5)
    p2, l2 = _run(path_ops.wrap_blockers, legs, perm, labels, seed=3)
    assert np.array_equal(np.sort(p2, axis=1), np.tile(np.arange(n), (100, 1)))
    assert np.array_equal(l2[:, [0, -1]], labels[:, [0, -1]])  # ends kept
    assert np.all(np.isin(l2[:, 1:-1], (-1, 0, 1)))
    for c in range(100):
        direct = legs.blocked[(1 + labels[c, 0]) // 2, 2 + (1 + labels[c, -1]) // 2]
        touched = np.count_nonzero(l2[c, 1:-1])
        assert (touched > 0) == direct  # a blocked direct leg gets something wrapped
        assert _blocked_pairs(p2[c], l2[c], legs.blocked) == [] or touched == n
    assert np.count_nonzero(l2[:, 1:-1], axis=1).mean() >= 2  # real paths, not direct ones


def _wraps_by_definition(n, first):
    """wrap_blockers by its definition, a move ``(key, perm, labels, legs)``: the repair's
    wrap (``_wrap_one``, which finds the next touched circle of any chromosome) applied
    n times to the chromosome with labels ``first .. n`` cleared (1: the direct path; 2:
    the path through position 0's obstacle), step t on words 3t .. 3t + 2 of 3n."""
    def move(key, p, l, legs):
        w = path_ops._words(key, 3 * n)

        def body(t, pl):
            return path_ops.apply(*pl, path_ops._wrap_one(
                jax.lax.dynamic_slice_in_dim(w, 3 * t, 3), *pl, legs)[0])
        return jax.lax.fori_loop(0, n, body, (p, l.at[first:-1].set(0)))
    return move


@pytest.mark.parametrize("make", [lambda: load_scenario("configs/scenarios/robocup_paper.toml"),
                                  _grid30,
                                  lambda: load_scenario("configs/scenarios/overlapping.toml")],
                         ids=["robocup", "grid30", "overlapping"])
def test_wrap_blockers_is_n_repair_wraps_with_the_touched_obstacles_first(make):
    """wrap_blockers is its definition, the repair's wrap (``_wrap_one``, which finds the
    next touched circle of any chromosome) applied n times from the cleared labels, step
    t on words 3t .. 3t + 2 of the key's 3n, and its chromosomes keep the touched
    obstacles at the front of the permutation."""
    sc = make()
    legs, n = _legs(sc), sc.n
    perm, labels = _random(n, 100, seed=7)
    p2, l2 = _run(path_ops.wrap_blockers, legs, perm, labels, seed=8)
    p3, l3 = _run(_wraps_by_definition(n, first=1), legs, perm, labels, seed=8)
    assert np.array_equal(p2, p3) and np.array_equal(l2, l3)
    touched = l2[:, 1:-1] != 0
    count = touched.sum(axis=1)
    assert np.array_equal(touched, np.arange(n)[None, :] < count[:, None])
    assert count.max() >= 2


def test_wrap_blockers_via_the_first_obstacle_is_n_repair_wraps_from_that_path():
    """With ``via``, wrap_blockers starts from the path through the permutation's first
    obstacle with its own label (the direct path where that label is 0) and is then the
    repair's wrap applied n times, the touched obstacles kept at the front; without it,
    the labels of position 0 do not matter (30 obstacles)."""
    sc = _grid30()
    legs, n = _legs(sc), sc.n
    perm, labels = _random(n, 100, seed=9)
    p2, l2 = _run(lambda k, p, l, g: path_ops.wrap_blockers(k, p, l, g, True), legs, perm,
                  labels, seed=8)
    p3, l3 = _run(_wraps_by_definition(n, first=2), legs, perm, labels, seed=8)
    assert np.array_equal(p2, p3) and np.array_equal(l2, l3)
    touched = l2[:, 1:-1] != 0
    count = touched.sum(axis=1)
    assert np.array_equal(touched, np.arange(n)[None, :] < count[:, None])
    # a chromosome whose first label is set keeps that obstacle touched (a later wrap
    # of it, as of any blocker, may turn it the other way)
    first = labels[:, 1] != 0
    assert first.any() and (~first).any()
    for c in np.flatnonzero(first):
        at = int(np.flatnonzero(p2[c] == perm[c, 0])[0])
        assert l2[c, 1 + at] != 0
    cleared = labels.copy()
    cleared[:, 1] = 0
    p4, l4 = _run(path_ops.wrap_blockers, legs, perm, labels, seed=8)
    p5, l5 = _run(path_ops.wrap_blockers, legs, perm, cleared, seed=8)
    assert np.array_equal(p4, p5) and np.array_equal(l4, l5)
    assert not np.array_equal(l2, l4)


def test_wrap_blockers_on_overlapping_circles_wraps_when_the_direct_leg_is_blocked():
    """Overlapping model circles make missing tangents whose stand-ins cross their own
    circles, so blocked legs may remain after n steps; still, a blocked direct leg
    always gets an obstacle wrapped, and a clear one none."""
    sc = load_scenario("configs/scenarios/overlapping.toml")
    legs, n = _legs(sc), sc.n
    perm, labels = _random(n, 100, seed=6)
    p2, l2 = _run(path_ops.wrap_blockers, legs, perm, labels, seed=4)
    assert np.array_equal(np.sort(p2, axis=1), np.tile(np.arange(n), (100, 1)))
    assert np.array_equal(l2[:, [0, -1]], labels[:, [0, -1]])
    for c in range(100):
        direct = legs.blocked[(1 + labels[c, 0]) // 2, 2 + (1 + labels[c, -1]) // 2]
        assert (np.count_nonzero(l2[c, 1:-1]) > 0) == direct


# --- legs: an independent check ----------------------------------------------------

def _segment_distance(p1, p2, q):
    """Distance from points q to segments p1-p2 (numpy, broadcasting, last axis xy)."""
    d = p2 - p1
    dd = np.sum(d * d, -1)
    t = np.clip(np.sum((q - p1) * d, -1) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    return np.linalg.norm(p1 + t[..., None] * d - q, axis=-1)


@pytest.mark.parametrize("make", [
    lambda: _scene([(1.0, 0.0), (1.2, 0.25, 0.05), (2.0, -0.3, 0.15), (2.5, 1.0)]),
    lambda: load_scenario("configs/scenarios/robocup_paper.toml")], ids=["hand", "robocup"])
def test_blockers_match_a_point_segment_distance_check(make):
    sc = make()
    sa = sc.search_arrays(np.float64, "full", with_legs=True)
    tb = sa.tangents
    n, C = sc.n, 2 * sc.n + 4
    L = legs_mod.build(tb, sc.centres, sc.model_radii)  # the tangents alone
    assert L.blockers.shape == (C, C, n) and L.blocked.shape == (C, C)
    assert L.blockers.dtype == bool and L.blocked.dtype == bool
    p1 = np.stack([tb.p1x, tb.p1y], -1)[:, :, None, :]
    p2 = np.stack([tb.p2x, tb.p2y], -1)[:, :, None, :]
    q = np.asarray(sc.centres, np.float64).reshape(n, 2)[None, None]
    expect = _segment_distance(p1, p2, q) < np.asarray(sc.model_radii)[None, None] - 1e-7
    assert np.array_equal(np.asarray(L.blockers), expect)
    assert np.array_equal(np.asarray(L.blocked), expect.any(-1))
    assert 0.05 < expect.any(-1).mean() < 0.95  # a real mix of clear and blocked legs
    # The search's legs add the goal arcs' blockers to the legs into a goal circle, and
    # change no other leg's (a start arc's obstacles make its leg bad, not blocked).
    ends = np.zeros((C, C), bool)
    ends[:, 2:4] = True
    got = np.asarray(sa.legs.blockers)
    assert np.array_equal(got[~ends], expect[~ends])
    assert np.all(got[ends] >= expect[ends])


def _arc_points(cx, cy, r, sign, a, b, count=2001):
    """Points along the circle (centre, radius, +1 CW / -1 CCW) from point a to point b."""
    a0 = np.arctan2(a[1] - cy, a[0] - cx)
    a1 = np.arctan2(b[1] - cy, b[0] - cx)
    sweep = np.mod(-sign * (a1 - a0), 2 * np.pi)  # CW: the angle falls
    t = a0 - sign * sweep * np.linspace(0.0, 1.0, count)
    return np.stack([cx + r * np.cos(t), cy + r * np.sin(t)], -1), r * sweep


@pytest.mark.parametrize("path", ["configs/scenarios/robocup_paper.toml",
                                  "configs/scenarios/cluttered.toml"])
def test_end_legs_carry_their_arcs_length_and_blockers_by_sampled_points(path):
    """A leg out of a start circle carries the start arc (start pose to its departure
    point), a leg into a goal circle the goal arc (its arrival point to the goal pose):
    their lengths against r x sweep measured here, their violations and blockers
    against points sampled along the arcs (an obstacle the points pass 1 mm inside
    makes the leg bad, and is a blocker of a goal arc's leg but for the obstacle at
    the leg's first circle; one they stay 1 mm clear of, and the segment too, is no
    blocker; a start arc adds none)."""
    sc = load_scenario(path)
    sa = sc.search_arrays(np.float64, "full", with_legs=True)
    tb, L = sa.tangents, sa.legs
    seg = legs_mod.build(tb, sc.centres, sc.model_radii)
    circles = np.asarray(tb.circles)
    centres = np.asarray(sc.centres, np.float64).reshape(-1, 2)
    radii = np.asarray(sc.model_radii, np.float64)
    start, goal = np.asarray(sc.start[:2]), np.asarray(sc.goal[:2])
    C, checked, met = circles.shape[0], 0, 0
    for a in range(C):
        for c in range(C):
            arcs = []
            if a < 2 and c >= 4:
                arcs.append(_arc_points(*circles[a], start, (tb.p1x[a, c], tb.p1y[a, c])))
            if 2 <= c < 4 and a >= 4:
                arcs.append(_arc_points(*circles[c], (tb.p2x[a, c], tb.p2y[a, c]), goal))
            if not arcs:
                continue
            checked += 1
            length = tb.length[a, c] + sum(x[1] for x in arcs)
            assert L.length[a, c] == pytest.approx(length, abs=1e-9)
            pts = np.concatenate([x[0] for x in arcs])
            d = np.linalg.norm(pts[:, None, :] - centres[None], axis=-1).min(0)
            inside, clear = d < radii - 1e-3, d > radii + 1e-3
            if a < 2:  # a start arc: its leg bad, no blockers added
                assert np.array_equal(L.blockers[a, c], seg.blockers[a, c])
            else:
                other = np.arange(len(radii)) == tb.obstacle[a]
                assert np.all(L.blockers[a, c][inside & ~other])
                assert not np.any(L.blockers[a, c] & other & ~seg.blockers[a, c])
            assert not np.any(L.blockers[a, c] & clear & ~seg.blockers[a, c])
            if np.any(inside):
                assert L.bad[a, c]
                met += 1
    assert checked > 50 and met > 0  # some end arcs meet an obstacle


@pytest.mark.parametrize("path", ["configs/scenarios/robocup_paper.toml",
                                  "configs/scenarios/overlapping.toml"])
def test_a_blocker_drawn_from_the_list_is_the_one_a_choice_over_the_row_takes(path):
    """``Legs.listed`` holds each tangent's blockers in index order (then the rest) and
    ``Legs.count`` how many; a word draws the same obstacle from them as a uniform choice
    over the True entries of ``blockers[a, c]`` (0 where the tangent has none)."""
    sc = load_scenario(path)
    L = sc.search_arrays(np.float32, with_legs=True).legs
    C = L.blocked.shape[0]
    assert np.array_equal(L.count, L.blockers.sum(-1))
    r = np.random.default_rng(3)
    a, c = r.integers(0, C, 4000).astype(np.int32), r.integers(0, C, 4000).astype(np.int32)
    w = r.integers(0, 2**32, 4000, dtype=np.uint64).astype(np.uint32)
    got = np.asarray(jax.jit(lambda a, c, w: path_ops._blocker(L, a, c, w))(a, c, w))
    row = np.asarray(L.blockers)[a, c]
    want = np.asarray(jax.jit(jax.vmap(lambda m, w: path_ops._choose(m, w)[0]))(row, w))
    np.testing.assert_array_equal(got, want)
    hits = row.any(-1)
    assert hits.mean() > 0.05 and (row.sum(-1) > 1).any()  # real draws among several
    assert row[np.arange(4000)[hits], got[hits]].all()  # always a blocker where there is one
    assert (got[~hits] == 0).all()


def test_blockers_worked_example():
    """Start (0, 0) and goal (2, 0), both heading 0, model radius 0.18: the outer
    tangent start CW -> goal CW runs along y = 0 through obstacle 0 at (1, 0), passes
    obstacle 1 at (1, 0.3) 0.3 m away (> 0.18), and obstacle 2 at (1, 0.18) exactly
    at its model radius (touching, not blocking)."""
    sc = _line_scene([(1.0, 0.0), (1.0, 0.3), (1.0, 0.18)])
    L = _legs(sc)
    assert L.blockers[1, 3].tolist() == [True, False, False]
    assert L.blocked[1, 3]
    # start CCW -> goal CCW (along y = 0 too): the same
    assert L.blockers[0, 2].tolist() == [True, False, False]


def test_legs_are_built_once_per_scenario_and_only_on_request():
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    assert sc.search_arrays().legs is None
    a = sc.search_arrays(with_legs=True).legs
    assert a is sc.search_arrays(with_legs=True).legs
    b = sc.search_arrays(np.float64, "full", with_legs=True).legs  # lengths per dtype
    assert a.blockers is b.blockers and a.bad is b.bad and a.arcs is b.arcs
    assert a.length.dtype == np.float32 and b.length.dtype == np.float64
    assert a.arcs.shape == (22, 22, 22) and sc.search_arrays(collision="paper",
                                                             with_legs=True).legs.arcs is not a.arcs
    assert isinstance(a, legs_mod.Legs) and a.blockers.shape == (22, 22, 9)


def test_n_above_onehot_limit_takes_the_gathers():
    assert 9 <= permutation.ONEHOT_MAX_N < 30  # the n = 30 scenes test the gather branch


# --- settings --------------------------------------------------------------------

@pytest.mark.parametrize("key, value, message", [
    ("path_mutation", "nope", "path_mutation: must be one of none, flip"),
    ("restart_after", -1, "restart_after: must be >= 0"),
    ("seeding", 1.5, "seeding: must be a probability in"),
    ("pm_path", float("nan"), "pm_path: must be a probability in"),
])
def test_bad_path_settings_are_refused(key, value, message):
    with pytest.raises(ConfigError, match=message):
        GASettings(**{key: value})
    with pytest.raises(ConfigError, match="x.toml: ga." + message):
        GASettings.from_mapping({key: value}, "x.toml")


@pytest.mark.parametrize("path_mutation", registry.names("path_mutation"))
@pytest.mark.parametrize("seeding", [0.0, 0.3, 1.0])
def test_uses_legs_iff_path_moves_or_seeding(path_mutation, seeding):
    s = GASettings(path_mutation=path_mutation, seeding=seeding, restart_after=4)
    assert s.uses_legs is (path_mutation != "none" or seeding > 0)


def test_register_move():
    def keep(key, perm, labels, legs):
        return perm, labels

    registry.register("path_mutation", "keep_for_test", keep)
    try:
        assert GASettings(path_mutation="keep_for_test").path_mutation == "keep_for_test"
        assert GASettings(path_mutation="keep_for_test").uses_legs
        with pytest.raises(ValueError, match="already registered"):
            registry.register("path_mutation", "keep_for_test", lambda *a: a[1:3])
    finally:
        registry.unregister("path_mutation", "keep_for_test")
    with pytest.raises(ConfigError, match="path_mutation"):
        GASettings(path_mutation="keep_for_test")


@pytest.mark.parametrize("n", [9, 25, 40])  # comparisons up to 20 obstacles, a suffix minimum beyond
def test_next_touched_is_the_first_touched_position_after_each(n):
    s = n + 2
    touched = np.random.default_rng(n).random((300, s)) < 0.3
    touched[:, 0] = touched[:, -1] = True  # the start and the goal are always touched
    got = np.asarray(jax.jit(jax.vmap(path_ops.next_touched))(touched))
    for row, t in zip(got, touched):
        want = [next((q for q in range(k + 1, s) if t[q]), s - 1) for k in range(s)]
        assert row.tolist() == want


@pytest.mark.parametrize("make", [_grid30, _cluttered30], ids=["grid30", "cluttered30"])
def test_a_clearer_wrap_takes_the_side_whose_new_legs_pass_fewer_obstacles(make):
    """``wrap_clearer`` (legs.clearer): with share 1 every wrap goes round the side of
    its obstacle whose two new legs (from the blocked leg's first circle to the
    obstacle, and on to its second) pass through fewer obstacles, counted here from the
    blocker table; where both pass as many, and with share 0, the random side as before;
    with 0.75 the words whose lowest 8 bits are below 192."""
    sc = make()
    legs = _legs(sc)
    n = sc.n
    blockers = np.asarray(legs.blockers)
    wrap = jax.jit(lambda w, p, l, lg: path_ops._wrap_one(w, p, l, lg))
    rng_ = np.random.default_rng(7)
    decided = 0
    for _ in range(150):
        perm = rng_.permutation(n).astype(np.int32)
        labels = rng_.choice([-1, 0, 0, 1], n + 2).astype(np.int32)
        labels[[0, -1]] = rng_.choice([-1, 1], 2)
        w = rng_.integers(0, 2**32, 3, dtype=np.uint64).astype(np.uint32)
        plain, ok = wrap(w, perm, labels, legs)
        if not ok:
            continue
        f = np.float32
        for share in (0.0, 0.75, 1.0):
            got, ok2 = wrap(w, perm, labels, legs._replace(clearer=f(share)))
            assert bool(ok2) and int(got.j) == int(plain.j) and int(got.i) == int(plain.i)
            # the wrapped leg: the positions around where the obstacle now sits
            new_perm, new_labels = path_ops.apply(perm, labels, got)
            ids = _circle_ids(np.asarray(new_perm), np.asarray(new_labels))
            o = int(perm[int(got.j)])
            at = [k for k, c in enumerate(ids) if c in (4 + 2 * o, 5 + 2 * o)][0]
            a, c = ids[at - 1], ids[at + 1]
            cw, ccw = 4 + 2 * o, 5 + 2 * o
            via_cw = blockers[a, cw].sum() + blockers[cw, c].sum()
            via_ccw = blockers[a, ccw].sum() + blockers[ccw, c].sum()
            on = share > 0 and (int(w[2]) & 0xFF) < 256 * share
            want = int(plain.label)
            if on and via_cw != via_ccw:
                want = 1 if via_cw < via_ccw else -1
                decided += share == 1.0
            assert int(got.label) == want, (share, via_cw, via_ccw)
    assert decided > 20  # the rule decided many of these wraps
