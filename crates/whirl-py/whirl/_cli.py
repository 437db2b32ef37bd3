"""The `whirl` command installed with the package: the command-line binary that a wheel
built by scripts/build-wheel carries in ``whirl/bin``. A source install has none."""

from __future__ import annotations

import os
import sys
from pathlib import Path


def binary() -> Path | None:
    """The bundled `whirl` binary, or None when this installation has none."""
    path = Path(__file__).with_name("bin") / ("whirl.exe" if os.name == "nt" else "whirl")
    return path if path.is_file() else None


def main() -> None:
    path = binary()
    if path is None:
        sys.exit(
            "error: this installation of the whirl package has no command-line binary (only "
            "the wheels of scripts/build-wheel carry one)\n"
            "  help: build it from a clone with `cargo build -p whirl-cli`"
        )
    os.execv(path, [str(path), *sys.argv[1:]])
