"""The README's Python block runs as written, from a folder holding the repository's
examples, as a new user would run it after the README's install line."""

from __future__ import annotations

import subprocess
import sys

from conftest import ROOT


def readme_python_block() -> str:
    """The ```python block of the README's `## From Python` section."""
    readme = (ROOT / "README.md").read_text()
    section = readme.split("\n## From Python\n", 1)[1]
    return section.split("```python\n", 1)[1].split("\n```", 1)[0]


def test_the_readme_block_is_the_tutorial():
    block = readme_python_block()
    assert "import whirl" in block
    assert "to_pandas" in block


def test_the_readme_python_block_runs(tmp_path):
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    done = subprocess.run(
        [sys.executable, "-c", readme_python_block()],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
