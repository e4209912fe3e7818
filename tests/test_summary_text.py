"""What a summary says of the settings comes from the settings the run used: every
operator's name and every rate, whatever registered the operator."""
import dataclasses

import pytest

from hga_jax.host.report import operators
from hga_jax.search import registry
from hga_jax.search.settings import PAPER, RECOMMENDED, GASettings


@pytest.mark.parametrize("base", [PAPER, RECOMMENDED], ids=["paper", "recommended"])
def test_every_operator_name_in_the_summary_is_the_one_used(registries, base):
    builtin = {kind: registry.names(kind) for kind in registry.KINDS}
    names = {}
    for kind in registry.KINDS:
        name = f"my_{kind}"
        registry.register(kind, name, lambda *a, **k: None)
        names[kind] = name
    st = dataclasses.replace(base, turns="reeds-shepp", **names)  # the model using every kind
    text = operators(st)
    for kind, name in names.items():
        assert name in text, kind
    words = set(text.replace(",", " ").replace(";", " ").replace(":", " ").split())
    for kind, known in builtin.items():
        for name in known:
            if name != "none":
                assert name not in words, f"{name} ({kind}) is named but not used"


def test_label_mutation_from_a_plugin_is_named_not_redraw(registries):
    registry.register("label_mutation", "swap_signs", lambda key, labels, rate: labels)
    text = operators(dataclasses.replace(PAPER, label_mutation="swap_signs"))
    assert "swap_signs mutation (pm 0.02 per gene)" in text and "redraw" not in text


def test_every_rate_and_count_is_the_run_s():
    st = GASettings(population=20, generations=7, pc_upper=0.31, pm_upper=0.07, pc_lower=0.29,
                    pm_lower=0.011, selection="tournament", tournament_size=5, elites=3,
                    turns="free", pc_legs=0.23, pm_legs=0.013, path_mutation="guided",
                    pm_path=0.17, seeding=0.25, restart_after=9, penalty_weight=4.5,
                    label_binding=[b for b in ("position", "obstacle")
                                   if b != PAPER.label_binding][0])
    text = operators(st)
    for said in ("size 5", "pc 0.31", "pm 0.07", "pc 0.29", "pm 0.011", "3 elites",
                 "pc 0.23", "pm 0.013", "pm 0.17", "25.00%", "9 stalled generations",
                 "penalty 4.5", f"bound by {st.label_binding}"):
        assert said in text, said


def test_a_study_brief_fits_the_terminal_with_long_names():
    from hga_jax.study.summary import brief

    rows = [{"group": g, "config": name, "hit_rate": h, "hit_rate_ci_low": max(0.0, h - 0.05),
             "hit_rate_ci_high": min(1.0, h + 0.05), "gap_median": 0.012,
             "feasible_rate": 1.0}
            for g in ("obstructed, 9 obstacles", "clusters, 25 obstacles")
            for name, h in (("random search, 2550 evaluations " * 4, 0.007),
                            ("HGA recommended, batched", 1.0))]
    for width in (60, 100):
        text = brief(rows, width)
        assert all(len(line) <= width for line in text.splitlines()), text
        assert "100.00% [95.00%, 100.00%]" in text and "0.70% [0.00%, 5.70%]" in text
    assert "HGA recommended, batched" in text
    assert "random search, 2550 evaluations random" in text and "..." in text  # shortened
