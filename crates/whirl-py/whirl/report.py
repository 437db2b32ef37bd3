"""The result of an analysis as the library reports it: a summary (``to_dict()``, what the
command line writes as summary.json) and named tables (``to_pandas(name)``, its CSV files),
the same numbers under the same names."""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _whirl
from ._summary import head
from .model import Model


class Report:
    """An analysis's result: its key numbers and its tables.

    ``result.to_dict()`` is the command line's summary.json (without the output folder and
    the file list), ``result.to_pandas("branch")`` one of its tables (``result.tables``
    names them), and ``result.columns("branch")`` the same table as numpy arrays. The
    summary's keys read as attributes too: ``result.points``.
    """

    __slots__ = ("command", "model", "_raw")

    def __init__(self, command: str, model: Model, raw: _whirl.Report):
        self.command = command
        self.model = model
        self._raw = raw

    @property
    def tables(self) -> tuple[str, ...]:
        """The names of the tables, in the order the command line writes them."""
        return tuple(self._raw.tables)

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        return {**head(self.command, self.model), **self._raw.summary()}

    def columns(self, table: str | None = None) -> dict[str, np.ndarray | list[str | None]]:
        """Table ``table`` (default the first) as its columns in order: numbers as float
        arrays (NaN where a value does not exist), counts (indices, iterations, records,
        0/1 flags) as int64 arrays, text as lists (None there)."""
        return self._raw.table(self.tables[0] if table is None else table)

    def to_pandas(self, table: str | None = None):
        """Table ``table`` (default the first) as a DataFrame: the command line's
        ``<table>.csv``, column for column."""
        import pandas as pd

        return pd.DataFrame(self.columns(table))

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        summary = self._raw.summary()
        if name not in summary:
            raise AttributeError(f"{type(self).__name__} has no `{name}`: its keys are {sorted(summary)}")
        return summary[name]

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), *self._raw.summary()})

    def __repr__(self) -> str:
        return f"<whirl {self.command} result of {self.model.name!r}: tables {', '.join(self.tables)}>"


class Reported:
    """A result with attributes of its own (branches, modes, ...) whose summary and tables
    are the library's report, ``self.report``; the summary's keys read as attributes too."""

    report: Report

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or name == "report":
            raise AttributeError(name)
        return getattr(self.report, name)

    @property
    def tables(self) -> tuple[str, ...]:
        """The names of the tables, in the order the command line writes them."""
        return self.report.tables

    def to_dict(self) -> dict[str, Any]:
        """The command line's summary.json (without the output folder and file list)."""
        return self.report.to_dict()

    def to_pandas(self, table: str | None = None):
        """Table ``table`` (default the first) as a DataFrame: the command line's
        ``<table>.csv``, column for column."""
        return self.report.to_pandas(table)
