"""Shared fixtures: the repository's example models and the command-line binary, whose
outputs the Python results are compared with."""

from __future__ import annotations

import json
import math
import os
import subprocess
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples"
REFERENCE = EXAMPLES / "reference_rotor.toml"


def cli_binary() -> Path:
    """The `whirl` binary built from this tree (scripts/test-all builds it first)."""
    given = os.environ.get("WHIRL_CLI")
    path = Path(given) if given else ROOT / "target" / "debug" / "whirl"
    if not path.exists():
        pytest.fail(f"no whirl binary at {path}: run `cargo build -p whirl-cli` or set WHIRL_CLI")
    return path


class CliRun:
    """One command-line run: its output folder, read back."""

    def __init__(self, out: Path, stderr: str):
        self.out = out
        self.stderr = stderr

    def summary(self) -> dict:
        summary = json.loads((self.out / "summary.json").read_text())
        # Where the folder went is the command line's own business.
        summary.pop("output_folder")
        summary.pop("files")
        return summary

    def table(self, name: str) -> pd.DataFrame:
        """A CSV table as the text of its cells (compared with :func:`assert_same_table`)."""
        return pd.read_csv(self.out / f"{name}.csv", dtype=str, keep_default_na=False)


def assert_same_table(python: pd.DataFrame, cli: pd.DataFrame):
    """The same columns in the same order and the same cells: numbers to the last bit
    (the CSV's shortest representations read back exactly by Python's float), empty cells
    where Python has NaN or None, text and booleans as written."""
    assert list(python.columns) == list(cli.columns)
    assert len(python) == len(cli)
    for name in cli.columns:
        for i, (value, cell) in enumerate(zip(python[name].tolist(), cli[name].tolist())):
            assert same_cell(value, cell), f"{name}[{i}]: python {value!r}, CLI {cell!r}"


def assert_matches_cli(result, cli: CliRun):
    """A Python result holds the command line's summary.json and every one of its tables."""
    assert result.to_dict() == cli.summary()
    for table in result.tables:
        assert_same_table(result.to_pandas(table), cli.table(table))


def same_cell(value, cell: str) -> bool:
    if cell == "":
        return value is None or value == "" or (isinstance(value, float) and math.isnan(value))
    if isinstance(value, bool) or isinstance(value, str):
        return str(value).lower() == cell.lower()
    return float(value) == float(cell)


@pytest.fixture
def run_cli(tmp_path):
    """Runs `whirl <args> --out DIR` and returns the folder; fails with the CLI's stderr."""

    def run(*args: str) -> CliRun:
        out = tmp_path / "cli-out"
        done = subprocess.run(
            [str(cli_binary()), *args, "--out", str(out)],
            capture_output=True,
            text=True,
            cwd=ROOT,
        )
        assert done.returncode == 0, done.stderr
        return CliRun(out, done.stderr)

    return run


@pytest.fixture
def run_cli_failing(tmp_path):
    """Runs a command expected to fail; returns its stderr."""

    def run(*args: str) -> str:
        done = subprocess.run(
            [str(cli_binary()), *args, "--out", str(tmp_path / "cli-out")],
            capture_output=True,
            text=True,
            cwd=ROOT,
            env={**os.environ, "NO_COLOR": "1"},
        )
        assert done.returncode != 0
        return done.stderr

    return run


def timeless(summary):
    """A summary without its computing times (``wall_time_s``, ``wall_s``, ``cpu_s`` at any
    depth): they differ between runs."""
    if isinstance(summary, dict):
        return {k: timeless(v) for k, v in summary.items() if k not in ("wall_time_s", "wall_s", "cpu_s")}
    if isinstance(summary, list):
        return [timeless(v) for v in summary]
    return summary
