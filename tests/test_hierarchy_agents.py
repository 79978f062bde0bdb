"""The hierarchy's robots in the project's one agent shape: workers and scouts are ``Robot``
subclasses whose behaviour is their own ``life()`` generator, ``model.agents`` is the one index of
them (nothing in the model or its members keeps a container of robots), and each director counts
what its own dispatches did (wave-order violations), which the summary sums."""

import inspect
from collections import Counter

import numpy as np
import pytest

from abm.robot import Robot
from models.hierarchy import HierarchyModel
from models.hierarchy.agents import Queen, Scout, Worker
from models.hierarchy.flat import FlatHolder, FlatScout
from models.hierarchy.planning import wave_order_violations, waves

QUICK = HierarchyModel.QUICK


def _ours(obj) -> bool:
    return type(obj).__module__.startswith("models.hierarchy") and hasattr(obj, "__dict__")


def _a_robot(x) -> bool:
    """A robot, or a wrapper of one (an object of this package holding a robot)."""
    if isinstance(x, Robot):
        return True
    return _ours(x) and any(isinstance(v, Robot) for k, v in vars(x).items() if k != "model")


def _robots_in(obj, path: str, seen: set[int]) -> list[str]:
    """Where ``obj`` (an object of this model's package, or a container) holds robots (or
    wrappers of robots) inside a container: a list, tuple, set or dict of them. Framework parts
    are not searched."""
    if id(obj) in seen:
        return []
    seen.add(id(obj))
    if isinstance(obj, dict):
        if any(_a_robot(x) for pair in obj.items() for x in pair):
            return [path]
        return [h for k, v in obj.items() for h in _robots_in(v, f"{path}[{k!r}]", seen)]
    if isinstance(obj, list | tuple | set | frozenset):
        if any(_a_robot(x) for x in obj):
            return [path]
        return [h for i, v in enumerate(obj) for h in _robots_in(v, f"{path}[{i}]", seen)]
    if _ours(obj):
        return [
            h
            for k, v in vars(obj).items()
            if k != "model"
            for h in _robots_in(v, f"{path}.{k}", seen)
        ]
    return []


@pytest.mark.parametrize("topology", ["hst", "star", "fc", "ring"])
def test_no_part_of_the_model_keeps_a_container_of_robots(topology):
    m = HierarchyModel(seed=1, topology=topology, **QUICK).run()
    seen: set[int] = set()
    hits = _robots_in(m, "model", seen)
    for member in [m.queen, *m.agents]:
        hits += _robots_in(member, type(member).__name__, seen)
    assert hits == []


def test_the_agents_are_the_role_classes_with_their_states_at_every_time():
    m = HierarchyModel(seed=2, **QUICK)
    w, s = QUICK["workers"], QUICK["scouts_per_worker"]
    assert {cls: len(agents) for cls, agents in m.agents_by_type.items()} == {
        Worker: w,
        Scout: w * s,
    }
    prefix = {Worker: "worker_", Scout: "scout_"}
    seen_states: set[str] = set()
    for t in (0.0, 5.0, 20.0, 40.0, 60.0, 90.0, None):
        m.run(until=t)
        by_state = Counter(robot.state for robot in m.agents)
        assert by_state == +Counter(m.recorder.counts), t  # the recorder's counts, exactly
        for cls, agents in m.agents_by_type.items():
            assert all(r.state.startswith(prefix[cls]) for r in agents), (t, cls)
            # a worker shows "directing" exactly while it runs an assignment
            if cls is Worker:
                assert all(r.directing == (r.state == "worker_directing") for r in agents)
        seen_states |= set(by_state)
    assert not m.running
    assert seen_states == set(m.STATES)  # every state was seen at one of the times
    assert isinstance(m.queen, Queen) and not isinstance(m.queen, Robot)
    assert m.queen not in m.agents


def test_each_robot_runs_its_own_classes_life_and_is_found_by_its_row():
    m = HierarchyModel(seed=3, **QUICK)
    for cls in (Worker, Scout, Queen):
        assert inspect.isgeneratorfunction(cls.__dict__["life"]), cls
    for robot in m.agents:
        assert robot.process is not None and robot.process.is_alive
        assert m.member(robot.id) is robot  # how every delivery finds its receiver
        assert np.array_equal(m.space.agent_positions[robot.row], robot.position)
    m.run()
    for robot in m.agents:
        assert m.member(robot.id) is robot
        assert np.array_equal(m.space.agent_positions[robot.row], robot.position)
    assert m.member(m.queen.id) is m.queen


@pytest.mark.parametrize("topology", ["fc", "ring"])
def test_the_flat_arms_hold_flat_scouts_and_a_bodiless_holder(topology):
    m = HierarchyModel(seed=4, topology=topology, **QUICK).run()
    n = QUICK["workers"] * QUICK["scouts_per_worker"]
    assert {cls: len(a) for cls, a in m.agents_by_type.items()} == {FlatScout: n}
    assert isinstance(m.queen, FlatHolder) and m.summary()["N"] == n + 1


def _recounted(m: HierarchyModel) -> Counter:
    """Each director's wave-order violations recounted from the recorded plans: per round, the
    idle children's moves and the placed children's moves are each dispatched in waves."""
    h = m.params.cell_size
    bubbles = m.events().query("event == 'bubble'")
    placed = {(d, int(r)): set(g["child"]) for (d, r), g in bubbles.groupby(["director", "round"])}
    out: Counter = Counter()
    rounds: dict[tuple[str, int], list[dict]] = {}
    for plan in m.plans:
        rounds.setdefault((str(plan["director"]), plan["round"]), []).append(plan)
    for key, plans in rounds.items():
        inside = placed.get(key, set())
        idle = {p["child"]: p["path"] for p in plans if str(p["child"]) not in inside}
        going = {
            p["child"]: p["path"] for p in plans if str(p["child"]) in inside and len(p["path"]) > 1
        }
        for moves in (idle, going):
            if moves:
                out[key[0]] += wave_order_violations(waves(moves, h), moves, h)
    return out


@pytest.mark.parametrize("seed", [2, 5])
def test_each_director_counts_its_own_wave_order_violations_and_the_summary_sums_them(seed):
    m = HierarchyModel(seed=seed, **QUICK).run()
    counts = {str(d.id): d.wave_order_violations for d in m.directors()}
    assert sum(counts.values()) == m.summary()["wave_order_violations"] > 0
    assert {k: v for k, v in counts.items() if v} == dict(+_recounted(m))
    off = HierarchyModel(seed=seed, wave_generator=False, **QUICK).run()
    assert [d.wave_order_violations for d in off.directors()] == [0] * (1 + QUICK["workers"])
