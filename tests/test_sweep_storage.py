"""A run's row file: written from the row's values with Arrow, read back exactly as the frame
pandas would have written, so a folder whose runs were written by either (a sweep resumed
across the change) reads as one dataset."""

import math

import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis.sweep.integrity import read_verified
from analysis.sweep.storage import _row_table, _write_atomic

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


def _same(a: pd.DataFrame, b: pd.DataFrame) -> bool:
    """The same columns, dtypes and values (NaN equal to NaN, sequences element by element)."""
    if list(a.columns) != list(b.columns) or not a.dtypes.equals(b.dtypes) or len(a) != len(b):
        return False
    for name in a.columns:
        x, y = a[name].iloc[0], b[name].iloc[0]
        if isinstance(x, float) and math.isnan(x):
            same = isinstance(y, float) and math.isnan(y)
        elif hasattr(x, "__len__") and not isinstance(x, str):
            same = list(x) == list(y)
        else:
            same = x == y
        if not same:
            return False
    return True


@settings(max_examples=150, deadline=None)
@given(row=st.dictionaries(NAMES, VALUES, min_size=1, max_size=12))
def test_a_row_reads_back_as_the_pandas_write_of_it(tmp_path_factory, row):
    row = {"run_id": "r-1", **row}
    folder = tmp_path_factory.mktemp("rows")
    _write_atomic(pd.DataFrame([row]), folder / "pandas.parquet")
    _write_atomic(_row_table(row), folder / "arrow.parquet")
    by_pandas = read_verified(folder / "pandas.parquet")
    by_arrow = read_verified(folder / "arrow.parquet")
    assert _same(by_arrow, by_pandas), (by_arrow.dtypes, by_pandas.dtypes)
    assert len(pd.concat([by_pandas, by_arrow])) == 2
