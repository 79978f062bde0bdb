"""A model reaches the framework and other models only through public names: nothing in
``models/`` reads or writes a private attribute of a model it is handed (``model._x``,
``self.model._x``); a model's own privates (``self._x``) are its business."""

import re
from pathlib import Path

MODELS = Path(__file__).resolve().parents[1] / "models"
#: ``model._name`` or ``<anything>.model._name``, but not a dunder (``model.__class__``).
PRIVATE = re.compile(r"\bmodel\._(?!_)\w+")


def test_no_model_code_touches_a_models_private_attributes():
    hits = [
        f"{path.relative_to(MODELS.parent)}:{number}: {line.strip()}"
        for path in sorted(MODELS.rglob("*.py"))
        for number, line in enumerate(path.read_text().splitlines(), 1)
        if PRIVATE.search(line)
    ]
    assert not hits, "models/ reaches a model's privates:\n" + "\n".join(hits)


def test_the_pattern_finds_what_it_should():
    assert PRIVATE.search("    model._detach_wanted.pop(rid, None)")
    assert PRIVATE.search("self.model._row_of[3]")
    assert not PRIVATE.search("self._detach_wanted.pop(rid)")
    assert not PRIVATE.search("model.__class__.__name__")
