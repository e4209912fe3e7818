"""The replanning study's file (hga_jax/loop/study.py): its keys, its one-line errors, and a
small study played by the command line against the batch it runs."""
from __future__ import annotations

import pytest

from hga_jax.errors import ConfigError
from hga_jax.loop import study


def _write(tmp_path, text: str):
    p = tmp_path / "rp.toml"
    p.write_text('kind = "replanning"\nname = "rp"\n' + text)
    return str(p)


def test_the_bundled_replanning_study_reads_as_written():
    st = study.load("configs/studies/replanning.toml")
    assert study.is_replanning("configs/studies/replanning.toml")
    assert not study.is_replanning("configs/studies/moving.toml")
    assert (st.episodes, st.host_episodes, st.time_limit) == (500, 50, 10.0)
    assert [(p.label, p.generations) for p in st.planners] == [
        ("hga", 5), ("hga-cold", 5), ("hga-cold x5", 25), ("sampler", 5), ("exact", 5)]
    assert [(f.name, f.kind, f.motion, f.robots) for f in st.families] == [
        ("crossing", "crossing", "constant", (5, 9)), ("leaving", "leaving", "constant", (5, 9)),
        ("random", "random_moving", "random", (5, 9)), ("chase", "random_moving", "chase", (5, 9))]
    quick = study.load("configs/studies/replanning.toml", quick=True)
    assert (quick.episodes, quick.host_episodes) == (40, 10)


@pytest.mark.parametrize("text, key", [
    ("episodes = 0\n[[families]]\nkind = 'crossing'\n", "episodes"),
    ("episode = 5\n[[families]]\nkind = 'crossing'\n", "episode"),
    ("[[families]]\nkind = 'crossing'\nmotion = 'teleport'\n", "families[0].motion"),
    ("[[families]]\nkind = 'nowhere'\n", "families[0].kind"),
    ("[[families]]\nkind = 'crossing'\nrobots = [1]\n", "families[0].robots"),
    ("[[planners]]\nname = 'rrt'\n[[families]]\nkind = 'crossing'\n", "planners[0].name"),
    ("", "families"),
])
def test_a_bad_key_is_one_line_naming_file_and_key(tmp_path, text, key):
    with pytest.raises(ConfigError) as e:
        study.load(_write(tmp_path, text))
    msg = str(e.value)
    assert msg.startswith(f"rp.toml: {key}: ") and "\n" not in msg


@pytest.mark.slow
def test_a_small_study_counts_what_its_batch_played(tmp_path, capsys):
    """Two episodes per cell by the command line: the table's counts are the episodes',
    each episode's outcome is the batch's for the same scene and seed, and a second call
    runs nothing again (its cells are kept)."""
    import pandas as pd

    from hga_jax.host.cli import main
    from hga_jax.loop import batch, episode

    path = _write(tmp_path, "seed = 3\nepisodes = 2\nhost_episodes = 1\ntime_limit = 3.0\n"
                  "[[planners]]\nname = 'hga'\n[[planners]]\nname = 'exact'\n"
                  "[[families]]\nname = 'x'\nkind = 'crossing'\nrobots = [5]\nseed = 11\n")
    out = tmp_path / "out"
    assert main(["study", path, "--out", str(out), "--quiet"]) == 0
    table = pd.read_csv(out / "replanning.csv")
    eps = pd.read_csv(out / "episodes.csv")
    assert list(table["episodes"]) == [2, 1]
    hga = eps[eps["planner"] == "hga"]
    st = study.load(path)
    scenes = [study.scene(st.families[0], 5, k) for k in range(2)]
    again = batch.run_batch(batch.scenes(scenes, [3, 4]),
                            episode.EpisodeSettings(time_limit=3.0))
    assert list(hga["outcome"]) == [batch.OUTCOMES[k] for k in again.outcome]
    assert table.loc[0, "reached"] == pytest.approx((hga["outcome"] == "reached").mean())
    before = sorted(p.stat().st_mtime for p in (out / "cells").iterdir())
    assert main(["study", path, "--out", str(out), "--quiet"]) == 0
    assert sorted(p.stat().st_mtime for p in (out / "cells").iterdir()) == before
