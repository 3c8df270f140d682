"""Rows are data: ``report`` and a resumed benchmark read rows against one schema.

A row's types are checked (``"success": "false"`` is refused, never counted as a success),
its sizes bounded; names are escaped in the Markdown a page gets and neutralised in CSV; and
``--into`` opens no FIFO, keeps the page's mode and writes through a symbolic link.
"""

from __future__ import annotations

import csv
import io
import json
import os
import stat
from pathlib import Path

import pytest

from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments.tables import results_table, success_csv
from radial_ibvs_agents.rows import check_row, load_rows, success_summaries

HOSTILE = "<!-- results:end --><script>alert(1)</script>|`x`"


def _row(policy: str = "ibvs", seed: int = 0, **changes: object) -> dict:
    row = {
        "policy": policy,
        "suite": "held-out",
        "variant": "random",
        "success": seed % 2 == 0,
        "end": "success" if seed % 2 == 0 else "time-out",
        "seed": seed,
        "collision": False,
        "final_position_error_m": 0.01,
        "final_heading_error_deg": 1.0,
        "success_by_tolerance": {"2cm/2deg": seed % 2 == 0, "10cm/5deg": True},
    }
    row.update(changes)
    return row


def _rows_file(tmp_path: Path, rows: object) -> Path:
    path = tmp_path / "episodes.json"
    path.write_text(json.dumps(rows))
    return path


@pytest.mark.parametrize(
    ("changes", "key"),
    [
        ({"success": "false"}, "success"),
        ({"success": 1}, "success"),
        ({"task": "7"}, "task"),
        ({"final_position_error_m": "NaN"}, "final_position_error_m"),
        ({"policy": "line\nbreak"}, "policy"),
        ({"policy": "x" * 10_000}, "policy"),
        ({"success_by_tolerance": {"2cm/2deg": "yes"}}, "success_by_tolerance"),
        ({"start_pose": [0.0, 1.0]}, "start_pose"),
        ({"extra": {"nested": {"deep": 1}}}, "extra"),
    ],
)
def test_a_row_that_breaks_the_schema_is_named(tmp_path: Path, changes: dict, key: str) -> None:
    path = _rows_file(tmp_path, [_row(seed=0), _row(seed=1, **changes)])
    with pytest.raises(ValueError, match=r"episodes\.json: row 1") as error:
        load_rows([path])
    assert repr(key) in str(error.value)


def test_rows_nested_without_end_are_refused(tmp_path: Path) -> None:
    path = tmp_path / "episodes.json"
    path.write_text("[" * 10_000 + "]" * 10_000)
    with pytest.raises(ValueError, match="nested deeper"):
        load_rows([path])


def test_a_rows_file_has_a_size_bound(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import radial_ibvs_agents.rows as rows_module

    monkeypatch.setattr(rows_module, "MAX_ROWS_BYTES", 64)
    path = _rows_file(tmp_path, [_row(seed=k) for k in range(4)])
    with pytest.raises(ValueError, match="MAX_ROWS_BYTES"):
        load_rows([path])


def test_a_hostile_name_is_escaped_in_the_page_and_neutralised_in_csv() -> None:
    rows = [_row(policy=HOSTILE, seed=k) for k in range(4)] + [_row(seed=k) for k in range(4)]
    for k, row in enumerate(rows):
        check_row(row, f"row {k}")  # printable text: the schema takes it
    table = results_table(rows)
    assert "<script>" not in table and "<!--" not in table
    assert "&lt;script&gt;" in table and "\\|" in table
    # the table's rows keep their cells: one more '|' per line than columns
    header, rule = table.splitlines()[:2]
    assert header.count(" | ") + 1 == rule.count("|") - 1
    summaries = success_summaries([_row(policy='=HYPERLINK("x")', seed=k) for k in range(2)])
    cells = list(csv.reader(io.StringIO(success_csv(summaries))))
    assert cells[1][2] == '\'=HYPERLINK("x")'


def test_into_regenerates_a_page_twice_whatever_the_names(tmp_path: Path) -> None:
    rows = _rows_file(tmp_path, [_row(policy=HOSTILE, seed=k) for k in range(4)])
    page = tmp_path / "README.md"
    page.write_text("top\n<!-- results:start -->\nold\n<!-- results:end -->\nbottom\n")
    assert main(["report", str(rows), "--into", str(page)]) == 0
    assert main(["report", str(rows), "--into", str(page)]) == 0  # the markers are intact
    text = page.read_text()
    assert text.count("<!-- results:end -->") == 1 and "<script>" not in text


def test_into_keeps_the_mode_and_writes_through_a_link(tmp_path: Path) -> None:
    rows = _rows_file(tmp_path, [_row(seed=k) for k in range(4)])
    page = tmp_path / "page.md"
    page.write_text("<!-- results:start -->\n<!-- results:end -->\n")
    os.chmod(page, 0o600)
    link = tmp_path / "link.md"
    link.symlink_to(page)
    assert main(["report", str(rows), "--into", str(link)]) == 0
    assert link.is_symlink() and "held-out: random" in page.read_text()
    assert stat.S_IMODE(page.stat().st_mode) == 0o600


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_into_a_fifo_is_refused_not_opened(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rows = _rows_file(tmp_path, [_row(seed=k) for k in range(4)])
    fifo = tmp_path / "page.md"
    os.mkfifo(fifo)  # opening it to read would wait for a writer forever
    assert main(["report", str(rows), "--into", str(fifo)]) == 2
    assert "not a regular file" in capsys.readouterr().err


def test_a_resumed_chunk_whose_rows_break_the_schema_runs_again() -> None:
    from radial_ibvs_agents.experiments.jobs import Job, JobResult
    from radial_ibvs_agents.experiments.store import _check
    from radial_ibvs_agents.experiments.suites import suite_variants

    variant = suite_variants(["random"])[0]
    job = Job("ibvs", variant, episodes=1)
    row = _row(seed=variant.seed_offset, suite=variant.suite, variant=variant.label)
    assert _check(JobResult(job, [row], [], None)) is None
    forged = {**row, "success": "true"}
    assert "'success'" in str(_check(JobResult(job, [forged], [], None)))
