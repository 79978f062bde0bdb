"""A run's row file: written from the row's values with Arrow, read back exactly as the frame
pandas would have written, so a folder whose runs were written by either (a sweep resumed
across the change) reads as one dataset; and a folder's rows joined in Arrow, shape by shape,
as pandas joined them one run at a time."""

import math

import pandas as pd
from hypothesis import example, given, settings
from hypothesis import strategies as st

from analysis.sweep.integrity import first_row, read_table_verified
from analysis.sweep.storage import _frames_by_shape, _row_table, _write_atomic

# the kinds of value a row holds: parameters and summaries (ints, floats with NaN and
# infinities, bools, text), None for an error that did not happen, tuples for a parameter
# given as a sequence
VALUES = st.one_of(
    st.integers(-(2**63), 2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
    st.booleans(),
    st.text(max_size=20),
    st.none(),
    st.tuples(st.floats(allow_nan=False, allow_infinity=False, width=32)).map(tuple),
)
NAMES = st.text(alphabet="abcdefghijklmnopqrstuvwxyz_", min_size=1, max_size=12)


def _read_as_pandas(path) -> pd.DataFrame:
    """A result file read as pandas reads it, its checksums verified."""
    return read_table_verified(path).to_pandas(use_threads=False)


def _same_cells(x: object, y: object) -> bool:
    """One cell of two frames: NaN equal to NaN, sequences element by element."""
    if isinstance(x, float) and math.isnan(x):
        return isinstance(y, float) and math.isnan(y)
    if hasattr(x, "__len__") and not isinstance(x, str):
        return hasattr(y, "__len__") and list(x) == list(y)
    return type(x) is type(y) and x == y


def _same(a: pd.DataFrame, b: pd.DataFrame) -> bool:
    """The same columns, dtypes and values of two one-row frames (:func:`_same_cells`)."""
    if list(a.columns) != list(b.columns) or not a.dtypes.equals(b.dtypes) or len(a) != len(b):
        return False
    return all(_same_cells(a[name].iloc[0], b[name].iloc[0]) for name in a.columns)


@settings(max_examples=150, deadline=None)
@given(row=st.dictionaries(NAMES, VALUES, min_size=1, max_size=12))
def test_a_row_reads_back_as_the_pandas_write_of_it(tmp_path_factory, row):
    row = {"run_id": "r-1", **row}
    folder = tmp_path_factory.mktemp("rows")
    _write_atomic(pd.DataFrame([row]), folder / "pandas.parquet")
    _write_atomic(_row_table(row), folder / "arrow.parquet")
    by_pandas = _read_as_pandas(folder / "pandas.parquet")
    by_arrow = _read_as_pandas(folder / "arrow.parquet")
    assert _same(by_arrow, by_pandas), (by_arrow.dtypes, by_pandas.dtypes)
    assert len(pd.concat([by_pandas, by_arrow])) == 2


# rows of a few shapes over a few column names, so that some rows share a shape and others not
SHAPED_ROWS = st.lists(
    st.tuples(st.dictionaries(st.sampled_from("abcd"), VALUES, max_size=4), st.booleans()),
    min_size=1,
    max_size=8,
)


@settings(max_examples=150, deadline=None)
@given(rows=SHAPED_ROWS)
# a column only NaN or only missing holds nothing (pandas drops it); rows of one shape written
# by either writer; a column int in one row and text in another
@example(rows=[({"a": math.nan}, False), ({"b": 1}, False), ({"c": None}, True)])
@example(rows=[({"a": 1.5, "b": "x"}, False), ({"a": 2.5, "b": "y"}, True), ({"a": 3.5}, False)])
@example(rows=[({"a": 1}, False), ({"a": "one"}, False), ({"a": (0.5,)}, False)])
def test_run_files_join_as_pandas_joins_their_frames(tmp_path_factory, rows):
    """A sweep's rows joined shape by shape in Arrow (:func:`_frames_by_shape`) give the frame
    pandas gives joining each run's frame without its empty columns, files written by Arrow or
    through pandas (a sweep resumed across that change) alike: the same columns in the same
    order, dtypes and values.
    """
    folder = tmp_path_factory.mktemp("shapes")
    paths = []
    for k, (values, by_pandas) in enumerate(rows):
        row = {"run_id": f"r-{k}", **values}
        paths.append(folder / f"r-{k}.parquet")
        _write_atomic(pd.DataFrame([row]) if by_pandas else _row_table(row), paths[-1])
    expected = pd.concat(
        [_read_as_pandas(p).dropna(axis=1, how="all") for p in paths], ignore_index=True
    ).sort_values("run_id", ignore_index=True)
    tables = [read_table_verified(p) for p in paths]
    joined = pd.concat(
        _frames_by_shape(tables, [first_row(t) for t in tables]), ignore_index=True
    ).sort_values("run_id", ignore_index=True)
    assert list(joined.columns) == list(expected.columns)
    assert joined.dtypes.equals(expected.dtypes), (joined.dtypes, expected.dtypes)
    for name in expected.columns:
        pairs = zip(joined[name].tolist(), expected[name].tolist(), strict=True)
        assert all(_same_cells(x, y) for x, y in pairs), (name, joined[name], expected[name])
