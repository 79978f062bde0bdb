"""The well-mixed diagnostic (analysis.macroscopic.mixing)."""

from rates_model import RatesModel

from analysis.macroscopic import collect_runs, well_mixed


def _diagnose(mixing: str):
    logs = collect_runs(RatesModel, range(700, 706), {"mixing": mixing})
    return well_mixed(logs, pairs=[("B", "C", "A"), ("A", "B", "C")], radius=3.0)


def test_a_model_that_is_not_well_mixed_is_flagged():
    """B -> C follows the A robots within 3 m, not all of them: local density explains
    much more of it than the global count, and the pair is flagged."""
    result = _diagnose("local")
    assert result.computable and result.flagged
    row = result.table.set_index(["source", "target", "k"]).loc[("B", "C", "A")]
    assert row["flagged"] and row["gap"] >= 0.05 and row["p_value"] < 0.01


def test_a_well_mixed_model_is_not_flagged():
    """The same swarm whose B -> C follows the global count of A is not flagged."""
    result = _diagnose("global")
    assert result.computable and not result.flagged
    row = result.table.set_index(["source", "target", "k"]).loc[("B", "C", "A")]
    assert row["r2_global"] > row["r2_local"]


def test_without_positions_the_diagnostic_says_it_cannot_be_computed():
    logs = collect_runs(RatesModel, [1, 2], {"trace_interval": None})
    result = well_mixed(logs)
    assert not result.computable and not result.flagged
    assert "trace_interval=None" in result.reason
