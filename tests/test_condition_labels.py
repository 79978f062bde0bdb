"""A report's curve panels label each line by its condition, the sweep parameters' values
joined by ", " (``analysis.figures.condition_labels``). Built a column at a time for speed, the
labels must be exactly the row-by-row join they replace, for any mix of parameter types.
"""

import pandas as pd
from hypothesis import given
from hypothesis import strategies as st

from analysis.figures import condition_labels

#: Values a sweep parameter takes: integers, finite floats, text and switches.
KINDS = (
    st.integers(-(10**6), 10**6),
    st.floats(allow_nan=False, allow_infinity=False, width=64),
    st.text(st.characters(codec="utf-8"), max_size=8),
    st.booleans(),
)


@st.composite
def swept(draw) -> tuple[pd.DataFrame, list[str]]:
    """A frame of 1-40 rows and 1-4 condition columns, each column of one value type."""
    rows = draw(st.integers(1, 40))
    columns = {}
    for i in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(KINDS))
        columns[f"p{i}"] = draw(st.lists(kind, min_size=rows, max_size=rows))
    return pd.DataFrame(columns), list(columns)


@given(swept())
def test_labels_are_the_row_by_row_join(case):
    data, conditions = case
    expected = data[conditions].astype(str).agg(", ".join, axis=1).to_numpy()
    assert list(condition_labels(data, conditions)) == list(expected)


def test_no_conditions_is_one_line_of_all_runs():
    assert condition_labels(pd.DataFrame({"t": [0.0, 1.0]}), []) == "all runs"
