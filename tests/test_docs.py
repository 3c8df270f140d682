"""The README's quick start stays true: CI runs its test command verbatim."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _quick_start_commands() -> list[str]:
    readme = (ROOT / "README.md").read_text()
    section = readme.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```(?:bash|sh)\n(.*?)```", section, flags=re.S)
    return [line.strip() for b in blocks for line in b.splitlines() if line.strip()]


def test_readme_has_two_quick_start_commands() -> None:
    commands = _quick_start_commands()
    assert len(commands) == 2, commands
    setup_and_demo, setup_and_test = commands
    assert "torch==2.13.0" in setup_and_demo and "radial-ibvs demo" in setup_and_demo
    assert "torch==2.13.0" in setup_and_test and "pytest" in setup_and_test


def test_ci_runs_the_readme_test_command_verbatim() -> None:
    test_command = _quick_start_commands()[1]
    ci = (ROOT / ".ci" / "run").read_text()
    assert test_command in ci.splitlines()


def test_readme_python_snippets_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every ```python block of the README runs, in order, in one namespace (in a scratch
    folder: the snippets save models)."""
    monkeypatch.chdir(tmp_path)
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    assert blocks
    namespace: dict[str, object] = {}
    for block in blocks:
        exec(compile(block, "README.md", "exec"), namespace)


#: rl-libraries.md runs its snippets as scripts, in a scratch folder (test_rl_libraries.py)
DOC_PAGES_WITH_CODE = sorted(
    p.name
    for p in (ROOT / "docs").glob("*.md")
    if "```python" in p.read_text() and p.name != "rl-libraries.md"
)


@pytest.mark.parametrize("page", DOC_PAGES_WITH_CODE)
def test_the_python_snippets_of_each_docs_page_run(
    page: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every ```python block of a docs page runs, in order, in one namespace per page.

    Illustrations that cannot run (a model directory of the reader's) are fenced ```py.
    """
    monkeypatch.chdir(tmp_path)  # what a snippet writes goes to a scratch folder
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / page).read_text(), flags=re.S)
    namespace: dict[str, object] = {}
    for block in blocks:
        exec(compile(block, page, "exec"), namespace)


def test_relative_links_in_the_readme_and_docs_point_to_files_that_exist() -> None:
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    pages.append(ROOT / "notebooks" / "README.md")
    pages += [ROOT / "research" / "README.md", ROOT / "research" / "learned-studies.md"]
    broken = []
    for page in pages:
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text()):
            if "://" in target:
                continue
            if not (page.parent / target).exists():
                broken.append(f"{page.relative_to(ROOT)} -> {target}")
    assert not broken, broken


def test_the_paper_to_code_map_names_code_and_tests_that_exist() -> None:
    text = (ROOT / "docs" / "paper-to-code.md").read_text()
    paths = set(re.findall(r"`((?:radial_ibvs_gym|agents|tests|configs)/[\w/.-]+)`", text))
    assert len(paths) > 20
    missing = sorted(p for p in paths if not (ROOT / p).exists())
    assert not missing, missing
