"""The docs cite the sources by author and year; one page lists them, one page the limitations."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: The seed files and the DOI of each source (docs/references.md; Kelso 2011 is a thesis).
SEEDS = {
    "000_3b7c4a8fe52a6eee.txt": "10.1155/2017/4027834",
    "001_2d0e0f624d8db633.txt": "10.1007/978-3-319-99272-3_36",
    "002_bb0c67d52fe8a188.txt": None,
    "003_83d3049daebcd276.txt": "10.4173/mic.2014.2.4",
}
SEED_NAME = re.compile(r"\b00[0-3]_[0-9a-f]{16}\.txt")
#: A seed by its bare number, as a source ("beside 000 Table 5", "000's rotor", "(000 eq. 32)").
SEED_NUMBER = re.compile(
    r"(?<![\w.,])(?<!\d )00[0-3](?:'s|:| Table| eqs?\.| §| Figs?\.| uses| writes| does)"
)


def test_readme_and_docs_cite_sources_by_author_and_year_not_by_file_name():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    for page in pages:
        if page.name == "references.md":
            continue
        assert not SEED_NAME.search(page.read_text(encoding="utf-8")), page.name


def test_code_models_scenarios_and_examples_cite_sources_by_author_and_year():
    # A user has the paper, not the project's seed file: messages, docstrings and comments
    # cite by author and year (docs/references.md maps them to the files).
    folders = ("pinwind", "tests", "examples", "benchmarks", "scenarios", "models")
    suffixes = {".py", ".pyi", ".hpp", ".cpp", ".toml", ".urdf", ".md", ".txt"}
    found = [
        str(path.relative_to(ROOT))
        for folder in folders
        for path in sorted((ROOT / folder).rglob("*"))
        if path.suffix in suffixes
        and path.name != Path(__file__).name
        and "__pycache__" not in path.parts
        and SEED_NAME.search(path.read_text(encoding="utf-8", errors="replace"))
    ]
    assert found == []


def test_package_cites_no_source_by_its_bare_seed_number():
    # "AGMA safety factors beside 000 Table 5" was printed by `pinwind sweep planetary`, and
    # "000 uses 24.5°" by a refused pressure angle: a user cannot know that 000 is Saleh 2017.
    found = [
        f"{path.relative_to(ROOT)}: {match.group(0)}"
        for path in sorted((ROOT / "pinwind").rglob("*"))
        if path.suffix in {".py", ".pyi", ".hpp", ".cpp"} and "__pycache__" not in path.parts
        for match in SEED_NUMBER.finditer(path.read_text(encoding="utf-8", errors="replace"))
    ]
    assert found == []


def test_references_list_each_source_with_its_doi_beside_its_file_name():
    rows = [
        line
        for line in (ROOT / "docs" / "references.md").read_text(encoding="utf-8").splitlines()
        if line.startswith("| ") and SEED_NAME.search(line)
    ]
    assert len(rows) == len(SEEDS)
    for seed, doi in SEEDS.items():
        (row,) = [r for r in rows if seed in r]
        if doi is not None:
            assert doi in row, seed
    for cite in ("Saleh 2017", "Kelso 2011", "Jørgensen 2014", "IFToMM 2018"):
        assert any(cite in r for r in rows), cite


def test_limitations_page_names_what_is_rigid_and_points_to_no_issue_tracker():
    text = (ROOT / "docs" / "limitations.md").read_text(encoding="utf-8")
    for named in ("Bearings", "ideal revolute", "Housing", "Friction", "Fatigue life"):
        assert named in text, named
    # A user has the docs, not the project's issue tracker: no "issue 24", no `issues show`.
    assert not re.search(r"\bissues? (show )?(N|\d+)\b", text), "limitations.md cites an issue"
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "docs/references.md" in readme and "docs/limitations.md" in readme


def test_user_docs_point_to_no_issue_tracker_and_to_no_test_or_compiled_source_file():
    # A user has the docs and the package, not the project's tracker: no "issue 24", no `issues
    # show N`; modules by their import name, not tests/… or the C++ sources. The code-layout page
    # is the maintainers' map and names files; the build's times name the unit they compiled.
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    file_name = re.compile(r"\btests/\w+|\bcpp/\w+|\w+\.hpp\b")
    for page in pages:
        if page.name == "code_layout.md":
            continue
        text = page.read_text(encoding="utf-8")
        assert not re.search(r"\bissues? (show )?(N|\d+)\b", text), page.name
        assert not file_name.search(text), (page.name, file_name.search(text))
