"""Every model's robots are exactly Mesa's ``model.agents``: at every change of a run the states
the recorder counts are those of ``model.agents`` and the space holds exactly those agents, and
no model (nor any part of it) keeps a list, set or dict of robots of its own beside it."""

from collections import Counter

import numpy as np
import pytest

from abm import registry
from abm.robot import Robot

#: A short run of every model (s of simulated time), long enough to launch robots.
SHORT = 150.0
ALL = sorted({*registry.model_names(), "tiny"})


@pytest.fixture(params=ALL)
def name(request, tiny_package) -> str:
    """Each model name; "tiny" comes from an entry point of a package made in the test."""
    return request.param


def _quick_model(name: str):
    cls = registry.model_class(name)
    return cls(seed=7, **{**cls.QUICK, "time_limit": SHORT})


def test_each_models_robots_are_its_agents_at_every_change(name):
    model = _quick_model(name)
    wrong: list[str] = []

    def check(*_args) -> None:
        agents = list(model.agents)
        if not all(isinstance(a, Robot) for a in agents):
            kinds = sorted({type(a).__name__ for a in agents if not isinstance(a, Robot)})
            wrong.append(f"t={model.time:g}: agents that are not robots: {kinds}")
        counted = {s: n for s, n in model.recorder.counts.items() if n}
        states = dict(Counter(a.state for a in agents))
        if counted != states:
            wrong.append(f"t={model.time:g}: counted {counted}, agents' states {states}")
        if set(model.space.active_agents) != set(agents):
            wrong.append(f"t={model.time:g}: the space's agents are not model.agents")

    for event in ("state", "failed", "removed"):
        model.lifecycle.subscribe(event, check)
    while model.running:
        model.step()
        check()
    assert len(model.agents) > 0
    assert not wrong, "\n".join(wrong[:5])


def _robots_held(value: object) -> bool:
    """True when ``value`` is a container that holds robots, or objects wrapping a robot (a
    robot index of its own)."""
    if isinstance(value, dict):
        items = [*value.keys(), *value.values()]
    elif isinstance(value, list | tuple | set | frozenset):
        items = list(value)
    elif isinstance(value, np.ndarray) and value.dtype == object:
        items = value.ravel().tolist()
    else:
        return False
    return any(isinstance(item, Robot) or _wraps_a_robot(item) for item in items)


def _wraps_a_robot(item: object) -> bool:
    return _ours(item) and any(isinstance(v, Robot) for v in getattr(item, "__dict__", {}).values())


def _ours(value: object) -> bool:
    module = type(value).__module__
    return module.startswith(("abm.", "models.", "tiny"))


def test_no_model_keeps_an_index_of_robots_beside_model_agents(name):
    model = _quick_model(name)
    model.run()
    holders = [("model", model)] + [
        (attr, part) for attr, part in vars(model).items() if _ours(part) and part is not model
    ]
    found = [
        f"{where}.{attr}" if where != "model" else f"model.{attr}"
        for where, owner in holders
        for attr, value in vars(owner).items()
        if _robots_held(value)
    ]
    assert not found, f"{name} keeps robots beside model.agents in: {', '.join(found)}"
