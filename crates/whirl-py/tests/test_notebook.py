"""Results at home in a notebook: a short repr, an HTML display with the summary and the
heads of the tables, pickling, flags as booleans and ``.plot()`` on each result."""

from __future__ import annotations

import pickle

import matplotlib
import numpy as np
import pytest

import whirl
from conftest import EXAMPLES, REFERENCE

matplotlib.use("Agg")

#: A repr is one line a person reads; the HTML a screenful, not the whole arrays (a
#: Campbell result printed 73 kB before).
REPR_CHARS = 400
HTML_CHARS = 20_000


@pytest.fixture(scope="module")
def model():
    return whirl.Model.from_file(REFERENCE)


@pytest.fixture(scope="module")
def results(model):
    return {
        "campbell": whirl.campbell(model, "0:800Hz:41", orders=[1, 2]),
        "modal": whirl.modal(model, "300Hz"),
        "cascade": whirl.cascade(model, "100Hz:400Hz:4", max_records=2, settle_max="1s", no_refine=True),
        "check": whirl.check(model),
        "hbm": whirl.hbm(model, "1:60Hz", harmonics=2),
    }


@pytest.mark.parametrize("name", ["campbell", "modal", "cascade", "check", "hbm"])
def test_the_repr_is_one_short_line(results, name):
    text = repr(results[name])
    print(f"{name}: repr {len(text)} chars, HTML {len(results[name]._repr_html_())} chars")
    assert "\n" not in text and len(text) < REPR_CHARS, text
    assert "reference rotor" in text
    for table in results[name].tables:
        assert table in text


@pytest.mark.parametrize("name", ["campbell", "modal", "cascade", "check", "hbm"])
def test_the_html_holds_the_summary_and_the_heads_of_the_tables(results, name):
    result = results[name]
    page = result._repr_html_()
    assert len(page) < HTML_CHARS
    assert page.count("<details>") == len(result.tables)
    first = result.tables[0]
    column = next(iter(result.to_pandas(first).columns))
    assert f"<th>{column}</th>" in page


@pytest.mark.parametrize("name", ["campbell", "modal", "cascade", "check", "hbm"])
def test_a_result_pickles_and_reads_back_the_same(results, name):
    result = results[name]
    back = pickle.loads(pickle.dumps(result))
    assert type(back) is type(result)
    assert back.to_dict() == result.to_dict()
    for table in result.tables:
        a, b = result.to_pandas(table), back.to_pandas(table)
        assert a.equals(b), table
    assert back.model.toml == result.model.toml


def test_flags_come_back_as_booleans(results):
    stable = results["hbm"].columns("branch")["stable"]
    assert stable.dtype == bool


@pytest.mark.parametrize("name", ["campbell", "modal", "cascade", "check", "hbm"])
def test_every_figure_of_a_result_draws(results, name):
    import matplotlib.pyplot as plt

    result = results[name]
    assert result.figures
    for kind in result.figures:
        ax = result.plot(kind)
        assert ax.has_data(), kind
        plt.close("all")


def test_a_cascade_of_one_start_has_no_figure_of_two(results):
    assert "starts" not in results["cascade"].figures


def test_an_unknown_figure_is_refused_naming_the_figures(results):
    with pytest.raises(ValueError, match="cascade_map"):
        results["cascade"].plot("bode")


def test_the_other_results_draw_their_default_figure(model):
    import matplotlib.pyplot as plt

    others = [
        whirl.convergence(model, [10, 20, 40], modes=2),
        whirl.unbalance(model, "1:300Hz:30", nodes=[10]),
        whirl.simulate(EXAMPLES / "reference_rotor.toml", "50Hz", duration="0.3s", settle="0.2s", reduce=12),
        whirl.static(model),
        whirl.fit_forcing(model, "100Hz:200Hz:2"),
    ]
    for result in others:
        assert np.isfinite(len(repr(result)))
        assert result.plot().has_data(), type(result).__name__
        plt.close("all")
