"""The README and the documents: every snippet runs as written, commands and links hold."""
import os
import re
import shlex
import tomllib
from pathlib import Path

import pytest

from hga_jax.host.cli import _parser

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def _blocks(lang: str) -> list[str]:
    """The README's fenced code blocks in language ``lang`` ("" for plain blocks)."""
    fences = re.findall(r"^```(\w*)\n(.*?)^```$", README, flags=re.S | re.M)
    return [body for kind, body in fences if kind == lang]


def test_ci_runs_exactly_the_readme_test_command():
    commands = [b.strip() for b in _blocks("") if "pytest" in b]
    assert len(commands) == 1
    ci = [line for line in (ROOT / ".ci" / "run").read_text().splitlines()
          if line and not line.startswith("#") and not line.startswith(("set ", "cd "))]
    assert ci == commands
    # a fresh environment that PEP 668 allows: a venv created and used in the command
    for block in _blocks(""):
        if "pip install" in block:
            assert block.strip().startswith("python3 -m venv .venv && . .venv/bin/activate && ")
    assert ".venv/" in (ROOT / ".gitignore").read_text().split()
    assert "3.11" in README and 'requires-python = ">=3.11"' in (ROOT / "pyproject.toml").read_text()


def test_synopsis_names_every_option():
    synopsis = next(b for b in _blocks("") if b.startswith("hga-jax run"))
    subs = _parser()._subparsers._group_actions[0].choices
    for name, sub in subs.items():
        part = re.search(rf"hga-jax {name} (.*?)(?=\nhga-jax |\Z)", synopsis, flags=re.S).group(1)
        written = set(re.findall(r"--[a-z-]+", part))
        options = {s for a in sub._actions for s in a.option_strings if s.startswith("--")}
        assert written == options - {"--help"}, name


def test_python_snippets_run_as_written(tmp_path, monkeypatch, registries):
    (tmp_path / "configs").symlink_to(ROOT / "configs")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for code in _blocks("python"):
        exec(compile(code, "README.md", "exec"), namespace)
    assert sorted(os.listdir("results/nb")) == ["convergence.png", "history.csv", "path.png",
                                                "result.json"]
    res, opt = namespace["res"], namespace["opt"]
    assert len(res.length) == 200 and opt.length == pytest.approx(2.24543, abs=1e-5)
    assert namespace["records"].best_fitness.shape == (11,)
    assert namespace["best"].perm.shape == (3, 9)


def test_scenario_snippet_loads():
    from hga_jax.host.config import scenario_from_dict

    (text,) = [b for b in _blocks("toml") if "[robot]" in b]
    sc = scenario_from_dict(tomllib.loads(text), "README.md")
    assert sc.name == "example" and sc.n == 1 and sc.ga == {"population": 50}


def test_documents_link_inside_the_repository():
    assert "docs/model.md" in README and (ROOT / "docs" / "model.md").is_file()
    texts = [README, (ROOT / "docs" / "model.md").read_text()]
    texts += [p.read_text() for p in (ROOT / "hga_jax").glob("*.py")]
    for text in texts:
        assert "MODEL.md" not in text and "performance notes" not in text
    for target in re.findall(r"\]\(([^)#]+)", README):
        assert (ROOT / target).exists(), target
    assert all(shlex.split(b) for b in _blocks(""))
