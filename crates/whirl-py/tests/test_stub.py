"""The hand-written type stub of the compiled module, whirl/_whirl.pyi, checked against the
module itself by mypy's stubtest: every function's parameters, every class and constant, and
the exported names must agree, so the stub cannot drift from what Rust exports."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path


def test_the_stub_matches_the_compiled_module():
    package = Path(__file__).resolve().parents[1]
    done = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "whirl._whirl"],
        cwd=package,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stdout + done.stderr
