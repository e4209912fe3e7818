"""What every held-out scene generator promises (``scattered``, ``clusters``,
``corridors``): scene ``i`` with ``n`` obstacles of seed ``s`` depends on ``(s, n, i)``
alone; every scene is blocked (the straight start-goal line and the four direct Dubins
paths collide) and its exact optimum is feasible, expressible and touches at least the
generator's count of obstacles; a study takes the kind, refuses a density (each scene
draws its own field) and too few obstacles. Each generator's own properties (radii,
fields, barriers) are tested in its own file, on the same scenes (:func:`pool`)."""
from __future__ import annotations

import functools
import re

import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.study import clusters, corridors, load_study, scattered
from hga_jax.study.scene_files import blocked
from hga_jax.study.scenes import generate

GENERATORS = {  # kind: module, (obstacles, seed) pairs, scenes of each, least touched
    "scattered": (scattered, ((6, 0), (6, 5), (12, 0), (12, 5)), 6, 2),
    "clusters": (clusters, ((9, 0), (9, 7), (15, 0), (15, 7)), 5, 3),
    "corridors": (corridors, ((9, 0), (9, 3), (15, 0), (26, 1)), 2, 2),
}


@functools.lru_cache(maxsize=None)
def pool(kind: str) -> dict[tuple[int, int, int], dict]:
    """The generator's test scenes: ``(n, seed, index) -> scenario mapping``."""
    _, pairs, count, _ = GENERATORS[kind]
    return {(n, s, i): generate(kind, n, s, i, f"{kind[0]}{n}_{i}")
            for n, s in pairs for i in range(count)}


@pytest.mark.parametrize("kind", GENERATORS)
def test_seeded_by_seed_count_and_index(kind):
    module, pairs, _, _ = GENERATORS[kind]
    (n, s), (_, other) = pairs[0], pairs[1]
    scenes = pool(kind)
    assert module.generate(n, s, 1, f"{kind[0]}{n}_1") == scenes[(n, s, 1)]
    assert scenes[(n, s, 0)] != scenes[(n, s, 1)]
    assert scenes[(n, s, 0)]["obstacles"] != scenes[(n, other, 0)]["obstacles"]


@pytest.mark.parametrize("kind", GENERATORS)
def test_every_scene_is_blocked_and_its_optimum_wraps_enough(kind):
    least = GENERATORS[kind][3]
    for (n, _, _), d in pool(kind).items():
        sc = scenario_from_dict(d)
        assert sc.n == n and blocked(sc)
        opt = solve(sc)
        assert opt.feasible and opt.expressible
        assert len({o for o, _ in opt.touched}) >= least


STUDY = ('name = "s"\nruns = 2\n[[families]]\nname = "fam"\nkind = "{kind}"\n'
         'obstacles = [{n}]\nscenes = 1\n{extra}[[configs]]\nlabel = "paper"\n')


@pytest.mark.parametrize("kind", GENERATORS)
def test_a_study_takes_the_kind_and_refuses_a_density_or_too_few(kind, tmp_path):
    least = GENERATORS[kind][3]
    (tmp_path / "ok.toml").write_text(STUDY.format(kind=kind, n=9, extra=""))
    assert load_study(str(tmp_path / "ok.toml")).families[0].kind == kind
    (tmp_path / "bad.toml").write_text(STUDY.format(kind=kind, n=9, extra="density = 1.0\n"))
    with pytest.raises(ConfigError, match=r"bad\.toml: families\[1\]\.density: not used by "
                                          rf"kind {kind}"):
        load_study(str(tmp_path / "bad.toml"))
    (tmp_path / "few.toml").write_text(STUDY.format(kind=kind, n=least - 1, extra=""))
    with pytest.raises(ConfigError, match=re.escape("few.toml: families[1].obstacles")):
        load_study(str(tmp_path / "few.toml"))
