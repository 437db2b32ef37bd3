"""Progress of long work: a tqdm bar when tqdm is installed, or the caller's callable."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import Any

Report = Callable[[int, int], bool | None]


@contextlib.contextmanager
def display(progress: bool | Report, what: str, unit: str) -> Iterator[Report | None]:
    """The callable handed to the library: ``progress`` itself when it is callable, a tqdm
    bar's update for True (nothing when tqdm is not installed), None for False."""
    if callable(progress):
        yield progress
        return
    if not progress:
        yield None
        return
    try:
        from tqdm.auto import tqdm
    except ImportError:
        yield None
        return
    bar = tqdm(desc=what, unit=f" {unit}", leave=False)

    def report(done: int, total: int) -> bool:
        bar.total = total
        bar.n = done
        bar.refresh()
        return False

    try:
        yield report
    finally:
        bar.close()


