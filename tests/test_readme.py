"""The README and the documents under docs/: every snippet runs as written, commands
parse, and links (with their #anchors) point inside the repository."""
import os
import re
import shlex
import tomllib
from pathlib import Path

import pytest

from hga_jax.host.cli import _parser

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
PAGES = [README] + sorted((ROOT / "docs").glob("*.md"))
FENCE = re.compile(r"^```(\w*)\n(.*?)^```$", flags=re.S | re.M)


def _blocks(page: Path, lang: str) -> list[str]:
    """The page's fenced code blocks in language ``lang`` ("" for plain blocks)."""
    return [body for kind, body in FENCE.findall(page.read_text()) if kind == lang]


def _name(page: Path) -> str:
    return str(page.relative_to(ROOT))


def _slug(heading: str) -> str:
    """The #anchor GitHub gives a heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(page: Path) -> set[str]:
    text = FENCE.sub("", page.read_text())
    return {_slug(h) for h in re.findall(r"^#+ (.*)$", text, flags=re.M)}


def test_ci_runs_exactly_the_readme_test_command():
    commands = [b.strip() for b in _blocks(README, "") if "pytest" in b]
    assert len(commands) == 1
    ci = [line for line in (ROOT / ".ci" / "run").read_text().splitlines()
          if line and not line.startswith("#") and not line.startswith(("set ", "cd "))]
    assert ci == commands
    # a fresh environment that PEP 668 allows: a venv created and used in the command
    for page in PAGES:
        for block in _blocks(page, ""):
            if "pip install" in block:
                assert block.strip().startswith(
                    "python3 -m venv .venv && . .venv/bin/activate && "), _name(page)
    assert ".venv/" in (ROOT / ".gitignore").read_text().split()
    text = README.read_text()
    assert "3.11" in text and 'requires-python = ">=3.11"' in (ROOT / "pyproject.toml").read_text()
    assert "jax>=0.10.2,<0.11" in text and '"jax>=0.10.2,<0.11"' in (
        ROOT / "pyproject.toml").read_text()


def test_readme_main_command_is_the_first_block():
    first = _blocks(README, "")[0].strip()
    assert first == ("python3 -m venv .venv && . .venv/bin/activate && pip install -e . && "
                     "hga-jax run configs/scenarios/robocup_paper.toml --runs 1000 --plot --force")


def test_synopsis_names_every_option():
    synopsis = next(b for b in _blocks(ROOT / "docs" / "cli.md", "") if b.startswith("hga-jax run"))
    subs = _parser()._subparsers._group_actions[0].choices
    for name, sub in subs.items():
        part = re.search(rf"hga-jax {name} (.*?)(?=\nhga-jax |\Z)", synopsis, flags=re.S).group(1)
        written = set(re.findall(r"--[a-z-]+", part))
        options = {s for a in sub._actions for s in a.option_strings if s.startswith("--")}
        assert written == options - {"--help"}, name


def test_commands_in_the_documents_parse_and_name_real_files():
    parser = _parser()
    for page in PAGES:
        for block in _blocks(page, ""):
            assert shlex.split(block) is not None, _name(page)
            for line in block.splitlines():
                line = re.sub(r"\s+#.*$", "", line).strip()
                for command in line.split("&&"):
                    words = shlex.split(command.strip().rstrip("&"))
                    placeholder = any(re.search(r"\[|[A-Z]{3}", w) for w in words)
                    if words[:1] == ["hga-jax"] and not placeholder:
                        parser.parse_args(words[1:])  # exits (fails) on a wrong option
                    for w in words:
                        if re.match(r"(configs|experiments|tests)/\S+\.(toml|py)$", w):
                            assert (ROOT / w).is_file(), f"{_name(page)}: {w}"


@pytest.mark.parametrize("page", [  # README.md's snippets in the default lane; docs/python.md's
    # run long GA batches (on demand, with -m slow)
    pytest.param(p, marks=pytest.mark.slow) if _name(p) == "docs/python.md" else p
    for p in PAGES if _blocks(p, "python")], ids=_name)
def test_python_snippets_run_as_written(page, tmp_path, monkeypatch, registries):
    (tmp_path / "configs").symlink_to(ROOT / "configs")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for code in _blocks(page, "python"):
        exec(compile(code, _name(page), "exec"), namespace)
    if page == README:
        assert sorted(os.listdir("results/nb")) == ["convergence.png", "history.csv", "path.png",
                                                    "result.json"]
        res, opt = namespace["res"], namespace["opt"]
        assert len(res.length) == 200 and opt.length == pytest.approx(2.24543, abs=1e-5)
    if page.name == "python.md":
        assert len(namespace["res"].length) == 200
        assert namespace["records"].best_fitness.shape == (11,)
        assert namespace["best"].perm.shape == (3, 9)
        bound, timed = namespace["bound"], namespace["timed"]  # robots that move
        assert not bound.optimal and bound.lower_bound == pytest.approx(3.0)
        assert timed.yardstick == "lower bound" and timed.best.violations_at == []
        assert timed.best.length == pytest.approx(bound.length, abs=1e-9)


def test_scenario_snippet_loads():
    from hga_jax.host.config import scenario_from_dict

    (text,) = [b for b in _blocks(README, "toml") if "[robot]" in b]
    sc = scenario_from_dict(tomllib.loads(text), "README.md")
    assert sc.name == "example" and sc.n == 1 and sc.ga == {"population": 50}


def test_toml_snippets_parse():
    for page in PAGES:
        for text in _blocks(page, "toml"):
            tomllib.loads(text)


def test_documents_link_inside_the_repository():
    readme = README.read_text()
    assert "docs/model.md" in readme
    for page in PAGES[1:]:  # every page under docs/ is reachable from the README
        assert f"](docs/{page.name})" in readme, page.name
    texts = [(p, p.read_text()) for p in PAGES]
    texts += [(p, p.read_text()) for p in (ROOT / "hga_jax").rglob("*.py")]
    for path, text in texts:
        assert "MODEL.md" not in text and "performance notes" not in text, path
    for page in PAGES:  # every file of the repository a page names is there
        for named in re.findall(r"\b(?:hga_jax|configs|experiments|tests)/[\w./*-]*\w",
                                page.read_text()):
            if not re.search(r"[A-Z]{3}", named):
                assert list(ROOT.glob(named)), f"{_name(page)}: {named}"
        for target in re.findall(r"\]\(([^)\s]+)\)", page.read_text()):
            if re.match(r"https?://", target):
                continue
            file, _, anchor = target.partition("#")
            dest = (page.parent / file).resolve() if file else page
            assert dest.exists() and ROOT in dest.parents, f"{_name(page)}: {target}"
            if anchor:
                assert anchor in _anchors(dest), f"{_name(page)}: {target}"


# The counts the documents quote (studies bundled, settings, tests) are checked in
# tests/test_doc_counts.py.
