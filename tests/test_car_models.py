"""The seam for car models (hga_jax.model.car_model): the registry, every model's own
rules on the same scenes, the rule that no code outside the model tests a model's
name, and the worked example of docs/model.md (configs/plugins/example_car.py): a new
model in one module and one registration, used from Python and the command line."""
from __future__ import annotations

import ast
import functools
import json
import math
import pathlib

import numpy as np
import pytest

from hga_jax import validation
from hga_jax.host.cli import main
from hga_jax.host.config import load_scenario
from hga_jax.model import car_model
from hga_jax.model.cars.free_turns import leg_space
from hga_jax.model.exact import solve
from hga_jax.model.no_path import exists
from hga_jax.running.results import json_safe
from hga_jax.running.runner import run_many
from hga_jax.search.settings import GASettings
from hga_jax.study import loops

ROOT = pathlib.Path(__file__).resolve().parents[1]
EXAMPLE = str(ROOT / "configs" / "plugins" / "example_car.py")
BUILT_IN = ("tight-rope", "free")


def _example():
    validation.load_plugins([EXAMPLE], "test", "plugins")
    return car_model.get("free-legs")


@functools.cache
def _scenes():
    """The bundled RoboCup scene and two loops scenes (free turns beat the tight rope),
    made on first use (not while the file is collected, in every worker)."""
    out = [load_scenario(ROOT / "configs" / "scenarios" / "robocup_paper.toml")]
    from hga_jax import scenario_from_dict

    for i in range(2):
        out.append(scenario_from_dict(loops.generate("loops", 3, 5, i, f"loops{i}"), f"loops{i}"))
    return out


SCENE_COUNT = 3


def test_registry_lists_the_papers_model_first_and_names_the_allowed_values():
    assert car_model.names()[:2] == BUILT_IN
    with pytest.raises(ValueError, match="must be one of tight-rope, free"):
        car_model.get("reeds")
    assert car_model.problem("free", "paper").startswith("free turns need the full")
    assert car_model.problem("free", "full") is None
    assert "must be one of" in car_model.problem(3, "full")


def test_a_name_is_registered_once(registries):
    class Other(car_model.CarModel):
        name = "free"

    with pytest.raises(ValueError, match="already registered"):
        car_model.register(Other())
    model = car_model.get("free")
    assert car_model.register(model) is model  # the same object again: nothing changes

    class Mine(car_model.CarModel):
        name = "mine"

    first = car_model.register(Mine())
    again = car_model.register(Mine())  # a notebook cell run again replaces it
    assert car_model.get("mine") is again is not first

    class Mine(car_model.CarModel):  # noqa: F811  (another class under that name)
        name = "mine"
        describe = "other"

    assert car_model.register(Mine()).describe == "other"

    class Else(car_model.CarModel):
        name = "mine"

    with pytest.raises(ValueError, match="already registered"):
        car_model.register(Else())


@pytest.mark.parametrize("name", BUILT_IN + ("reeds-shepp",))
@pytest.mark.parametrize("k", range(SCENE_COUNT))
def test_each_model_answers_for_itself(name, k):
    """Every model's optimum is feasible where its graph joins start and goal, records
    its own name, writes a JSON-safe dict with the keys it adds, and a free-turn optimum
    is never longer than the tight rope's."""
    assert len(_scenes()) == SCENE_COUNT
    sc, model = _scenes()[k], car_model.get(name)
    opt = solve(sc, "full", name)
    assert opt.turns == name and opt.feasible == exists(sc, "full", name)
    d = json.loads(json.dumps(json_safe(opt.to_dict()), allow_nan=False))
    assert set(model.extras(opt)) <= set(d)
    if name != "tight-rope":  # every tight-rope path is a free-turn and a Reeds-Shepp path
        tight = solve(sc, "full").length
        assert opt.length <= tight + 1e-9 and d["tight_rope_length"] == pytest.approx(tight)


def _string_constants(path: pathlib.Path) -> list[tuple[int, str]]:
    """String constants of a module that are not docstrings, with their lines."""
    tree = ast.parse(path.read_text())
    docs = {id(node.body[0].value) for node in ast.walk(tree)
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
            and node.body and isinstance(node.body[0], ast.Expr)
            and isinstance(node.body[0].value, ast.Constant)}
    return [(node.lineno, node.value) for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and id(node) not in docs]


def test_no_code_outside_the_model_names_a_car_model():
    """The GA loop, runner, CLI, study, peers, plots and reports ask the model: no string
    constant outside hga_jax/model/ is a model's name (so none is tested against)."""
    names = set(car_model.names())
    found = [f"{p.relative_to(ROOT)}:{line}: {value!r}"
             for p in sorted((ROOT / "hga_jax").rglob("*.py"))
             if "model" not in p.relative_to(ROOT / "hga_jax").parts[:1]
             for line, value in _string_constants(p) if value in names]
    assert found == []


def test_the_example_model_is_one_module_and_one_registration():
    model = _example()
    assert model.name in car_model.names() and model.genes == car_model.get("free").genes
    assert "free-legs" in GASettings(turns="free-legs").turns
    for sc in _scenes()[1:]:
        free, legs, tight = (solve(sc, "full", t) for t in ("free", "free-legs", "tight-rope"))
        assert legs.length == pytest.approx(leg_space.shortest(sc)[0], abs=1e-12)
        assert free.length <= legs.length + 1e-9 <= tight.length + 2e-9
        assert legs.to_dict()["turns"] == "free-legs"
    with pytest.raises(Exception, match="free turns need the full collision test"):
        GASettings(turns="free-legs", collision="paper")


def test_the_example_model_runs_from_python_and_the_command_line(tmp_path, capsys):
    _example()
    sc = _scenes()[1]
    st = GASettings(population=20, generations=20, turns="free-legs")
    res = run_many(sc, st, seed=1, runs=8)
    assert res.optimum.turns == "free-legs" and res.legs is not None
    s = res.summary()
    assert s["optimum_turns"] == "free-legs"
    assert math.isclose(s["optimum_length"], leg_space.shortest(sc)[0], abs_tol=1e-12)
    path = tmp_path / "loops.toml"
    from hga_jax.model.scenario import scenario_to_dict
    import tomli_w

    path.write_text(tomli_w.dumps(scenario_to_dict(sc)))
    code = main(["exact", str(path), "--plugin", EXAMPLE, "--turns", "free-legs",
                 "--out", str(tmp_path / "out")])
    printed = capsys.readouterr().out
    assert code == 0 and "free-leg optimum" in printed and "tight-rope optimum" in printed
    data = json.loads((tmp_path / "out" / "result.json").read_text())
    assert data["optimum"]["turns"] == "free-legs"
    assert np.isclose(data["optimum"]["length"], leg_space.shortest(sc)[0], atol=1e-12)
