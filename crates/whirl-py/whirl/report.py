"""The result of an analysis as the library reports it: a summary (``to_dict()``, what the
command line writes as summary.json) and named tables (``to_pandas(name)``, its CSV files),
the same numbers under the same names."""

from __future__ import annotations

import copy
from typing import Any

import numpy as np

from . import _whirl
from ._display import Display
from ._summary import head
from .model import Model

#: The figures only :mod:`whirl.plot` draws of each command's report (with options the
#: command line's figures, which every report has, do not take).
_FIGURES = {
    "hbm": ("hb_branch",),
    "stiffness": ("stiffness",),
}
#: A text column of these values only is a column of flags.
_FLAG_TEXT = {"true": True, "false": False}


class Report(Display):
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
        columns = self._raw.table(self.tables[0] if table is None else table)
        return {name: _flags_as_bool(values) for name, values in columns.items()}

    def to_pandas(self, table: str | None = None):
        """Table ``table`` (default the first) as a DataFrame: the command line's
        ``<table>.csv``, column for column."""
        import pandas as pd

        return pd.DataFrame(self.columns(table))

    def figure_specs(self) -> list[dict[str, Any]]:
        return self._raw.figures()

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        summary = self._raw.summary()
        if name not in summary:
            raise AttributeError(f"{type(self).__name__} has no `{name}`: its keys are {sorted(summary)}")
        return summary[name]

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), *self._raw.summary()})

    @property
    def _figures(self) -> tuple[str, ...]:
        return _FIGURES.get(self.command, ())

    def _report(self) -> Report:
        return self

    def __reduce__(self):
        # The compiled report does not pickle: its summary and tables, as read, do.
        raw = _Read(self._raw.summary(), {t: self._raw.table(t) for t in self.tables}, self._raw.figures())
        return (_restored, (type(self), self.command, self.model, raw))


def _restored(cls: type[Report], command: str, model: Model, raw: _Read) -> Report:
    report = cls.__new__(cls)
    Report.__init__(report, command, model, raw)
    return report


class _Read:
    """A report's summary and tables as read from the compiled one, with its interface: what
    an unpickled :class:`Report` holds."""

    __slots__ = ("_summary", "_tables", "_figures")

    def __init__(self, summary: dict[str, Any], tables: dict[str, dict[str, Any]], figures: list[dict[str, Any]]):
        self._summary = summary
        self._tables = tables
        self._figures = figures

    @property
    def tables(self) -> list[str]:
        return list(self._tables)

    def summary(self) -> dict[str, Any]:
        return copy.deepcopy(self._summary)

    def figures(self) -> list[dict[str, Any]]:
        return copy.deepcopy(self._figures)

    def table(self, name: str) -> dict[str, Any]:
        if name not in self._tables:
            raise _whirl.InputError(f"no table `{name}`: the tables are {', '.join(self._tables)}")
        return copy.deepcopy(self._tables[name])


def _flags_as_bool(values: Any) -> Any:
    """A text column of only "true" and "false" (the CSV's flags) as a bool array."""
    if not isinstance(values, list) or not values or any(v not in _FLAG_TEXT for v in values):
        return values
    return np.array([_FLAG_TEXT[v] for v in values], dtype=bool)


class Reported(Display):
    """A result with attributes of its own (branches, modes, ...) whose summary and tables
    are the library's report, ``self.report``; the summary's keys read as attributes too."""

    report: Report

    def _report(self) -> Report:
        return self.report

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
