"""The counts and figures the documents quote match the code and each other: the bundled
studies and scenarios, the GA settings' table, the README's results table against
docs/results.md, and figures stated in one place only (compile times and test counts live
in docs/performance.md). Files only, no JAX: well under a second."""
import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
PAGES = [README] + sorted(DOCS.glob("*.md"))
# pages that hold measurements with their date and machine; the others link to them
MEASURED = {DOCS / "performance.md", DOCS / "results.md"}

NUMBERS = {w: i for i, w in enumerate(
    "zero one two three four five six seven eight nine ten eleven twelve thirteen fourteen "
    "fifteen sixteen seventeen eighteen nineteen twenty".split())}


def _name(page: Path) -> str:
    return str(page.relative_to(ROOT))


def _prose(page: Path) -> str:
    """The page's text on one line per paragraph (a sentence may span lines)."""
    return re.sub(r"[ \t]*(?<!\n)\n(?!\n)[ \t]*", " ", page.read_text())


def _section(page: Path, heading: str) -> str:
    """The text under ``## heading`` up to the next heading of level two."""
    text = page.read_text()
    start = text.index(f"\n## {heading}\n")
    end = text.find("\n## ", start + 1)
    return text[start:end if end >= 0 else len(text)]


def _rows(markdown: str) -> list[list[str]]:
    """The body rows of the first Markdown table in ``markdown``, as stripped cells."""
    lines = [ln for ln in markdown.splitlines() if ln.startswith("|")]
    assert len(lines) >= 3, "no table"
    return [[c.strip() for c in ln.strip().strip("|").split("|")] for ln in lines[2:]]


def test_the_documents_count_and_list_the_bundled_studies():
    bundled = sorted(p.name for p in (ROOT / "configs" / "studies").glob("*.toml"))
    studies = DOCS / "studies.md"
    listed = sorted(re.findall(r"^\| `(\w+\.toml)` \|", studies.read_text(), flags=re.M))
    assert listed == bundled  # the table of docs/studies.md: one row per bundled file
    for page in (README, studies):
        said = re.findall(r"\b(\w+) (?:studies )?are bundled", _prose(page))
        assert said, f"{_name(page)} no longer says how many studies are bundled"
        for word in said:
            assert NUMBERS.get(word.lower()) == len(bundled), (
                f"{_name(page)} says {word} studies are bundled; there are {len(bundled)}")


def test_the_readme_lists_every_bundled_scenario():
    bundled = sorted(p.name for p in (ROOT / "configs" / "scenarios").glob("*.toml"))
    paragraph = re.search(r"Bundled: (.*?)\n\n", README.read_text(), flags=re.S).group(1)
    assert sorted(re.findall(r"`(\w+\.toml)`", paragraph)) == bundled


def _settings_fields() -> list[str]:
    """The fields of GASettings, read from its source (no import of JAX)."""
    tree = ast.parse((ROOT / "hga_jax" / "search" / "settings.py").read_text())
    cls = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "GASettings")
    return [n.target.id for n in cls.body
            if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)]


def test_the_settings_table_names_every_setting_once():
    fields = _settings_fields()
    assert len(fields) == len(set(fields)) and len(fields) > 30
    rows = _rows(_section(DOCS / "settings.md", "GA settings"))
    keys = [k for row in rows for k in re.findall(r"`(\w+)`", row[0])]
    assert len(keys) == len(set(keys)), "a setting has two rows"
    assert set(keys) <= set(fields), f"rows of no setting: {set(keys) - set(fields)}"
    # a setting without a row of its own is named in the row it belongs to
    # (tournament_size in the selection row)
    named = {k for row in rows for k in re.findall(r"`(\w+)`", " ".join(row))}
    assert set(fields) <= named, f"settings the table leaves out: {set(fields) - named}"
    for page in PAGES:  # any count of the settings a page quotes
        for number in re.findall(r"\b(\w+) (?:GA )?settings? keys\b|\b(\w+) GA settings\b",
                                 _prose(page)):
            word = next(w for w in number if w)
            if word.isdigit() or word.lower() in NUMBERS:
                n = int(word) if word.isdigit() else NUMBERS[word.lower()]
                assert n == len(fields), f"{_name(page)}: {word} settings; {len(fields)} fields"


def test_no_page_quotes_a_count_of_tests():
    """The number of tests changes with every commit: pages do not quote it (pytest
    --collect-only prints it); docs/performance.md's history names the version of each."""
    count = re.compile(r"\b\d[\d,]* (?:\w+ )?tests\b")
    for page in PAGES:
        if page in MEASURED:
            continue
        assert not count.findall(_prose(page)), f"{_name(page)}: {count.findall(_prose(page))}"
    glance = _section(DOCS / "performance.md", "At a glance")
    assert not count.findall(re.sub(r"\s+", " ", glance))


def test_compile_times_are_stated_in_one_place():
    """Cold and warm compile times: one statement, with its date and machine, in
    docs/performance.md (At a glance); other pages link there."""
    timed = re.compile(r"compil\w*[^.;\n]{0,80}?\b\d+(?:\.\d+)?(?:-\d+(?:\.\d+)?)? ?s\b"
                       r"|\b\d+(?:\.\d+)? ?s\b[^.;\n]{0,40}?compil", flags=re.I)
    for page in PAGES:
        if page in MEASURED:
            continue
        assert not timed.findall(_prose(page)), (
            f"{_name(page)} quotes compile times {timed.findall(_prose(page))}: state them "
            "once in docs/performance.md (with date and machine) and link there")
    glance = _section(DOCS / "performance.md", "At a glance")
    rows = {row[0]: row for row in _rows(glance)}
    cold = next(r for q, r in rows.items() if "cold" in q and "compile" in q)
    warm = next(r for q, r in rows.items() if "warm" in q)
    for row in (cold, warm):  # a figure, a version, a date and a machine
        assert re.search(r"\d s", row[1]), row
        assert re.search(r"\b0\.\d+\.\d+\b", row[2]) and re.search(r"20\d\d-\d\d-\d\d", row[2])
        assert "machine" in row[2]
    for page in (README, DOCS / "cli.md"):
        assert "performance.md#at-a-glance" in page.read_text(), _name(page)


def test_the_readme_results_table_quotes_docs_results():
    """The README's table of the paper's scene quotes docs/results.md, figure for figure."""
    readme = _rows(_section(README, "Results on the paper's scene"))
    results = _rows(_section(DOCS / "results.md", "The paper's scene: four planners side by side"))
    assert len(readme) == len(results) == 4
    for ours, theirs in zip(readme, results):
        assert ours[0].split(",")[0] == theirs[0].split(",")[0]  # HGA, HGA, exact, OMPL
        assert ours[1].startswith("`hga-jax "), ours  # the command that makes the row
        # hit rate, feasible, median gap, time per run: the same columns in both tables
        for mine, stated in zip(ours[2:], theirs[2:], strict=True):
            assert stated == mine or stated.startswith(mine + " "), (
                f"README says {mine!r}, docs/results.md {stated!r} ({ours[0]})")


def test_the_readme_is_short_and_names_both_cars():
    lines = README.read_text().splitlines()
    assert len(lines) <= 250
    assert "Dubins" in lines[0] and "Reeds–Shepp" in lines[0]
    assert "(CHANGELOG.md)" in README.read_text() and (ROOT / "CHANGELOG.md").is_file()
    changelog = (ROOT / "CHANGELOG.md").read_text()
    version = re.search(r'__version__ = "([^"]+)"',
                        (ROOT / "hga_jax" / "__init__.py").read_text()).group(1)
    assert f"## [{version}] - " in changelog  # the current version has its section
    versions = re.findall(r"^## \[(\d+)\.(\d+)\.(\d+)\]", changelog, flags=re.M)
    as_tuples = [tuple(map(int, v)) for v in versions]
    assert as_tuples == sorted(as_tuples, reverse=True)  # newest first
