"""Speed work changes no behaviour: seeded runs of every model give the stored event logs.

The digests in ``tests/data/event_digests.json`` were written by ``scripts/event_digests.py
--write`` on the revision before the scale work; a branch that changes a model's behaviour on
purpose regenerates them (see the script's docstring).
"""

import importlib.util
from pathlib import Path

import pytest

_SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "event_digests.py"
_spec = importlib.util.spec_from_file_location("event_digests", _SCRIPT)
event_digests = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(event_digests)


@pytest.mark.parametrize("case", event_digests.QUICK)
def test_seeded_run_matches_stored_digest(case):
    want = event_digests.stored().get(case)
    assert want is not None, f"no stored digest for {case}: run scripts/event_digests.py --write"
    assert event_digests.digest(case) == want


def test_paper_default_worlds_match_stored_digest():
    want = event_digests.stored().get(event_digests.WORLDS)
    assert want is not None
    assert event_digests.world_digest() == want
