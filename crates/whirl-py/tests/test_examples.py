"""Every script of examples/python runs as written, from the repository's root."""

from __future__ import annotations

import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = sorted((ROOT / "examples" / "python").glob("*.py"))


def test_there_are_examples():
    assert len(EXAMPLES) >= 4


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(script, tmp_path):
    # Each example writes under out/ of the folder it runs in: a scratch copy of the
    # layout it expects (examples/ and the ROSS fixtures), so the tree stays clean.
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    (tmp_path / "crates").symlink_to(ROOT / "crates")
    done = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip()
