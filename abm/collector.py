"""Mesa's DataCollector with Mesa's step count as its key, and simulated time as a column.

Mesa 3.5 keys each collection by ``model.time``, which ``mesa.batch_run`` reports as the
``Step`` of each row. In a SwarmModel ``model.time`` is the SimPy clock's simulated seconds
(one ``step()`` advances ``step_duration`` s), so ``Step`` read 0.5, 5.5, ... where Mesa users
expect step counts. This collector keys each collection by ``model.steps`` and records the
simulated time in a ``time`` column (s) of its own.
"""

from collections.abc import Callable, Mapping

import mesa

__all__ = ["StepCollector"]


class StepCollector(mesa.DataCollector):
    """A DataCollector of ``model_reporters`` plus ``time`` (s), keyed by the step count."""

    def __init__(self, model_reporters: Mapping[str, Callable]) -> None:
        super().__init__(model_reporters={"time": _time, **model_reporters})

    def collect(self, model: mesa.Model) -> None:
        """Collect every reporter; the collection's key is ``model.steps``, not the time."""
        super().collect(model)
        # Mesa appends model.time to the keys batch_run reads back as "Step" (mesa 3.5's
        # DataCollector.collect); in a SwarmModel that is seconds, so the key is replaced.
        self._collection_steps[-1] = model.steps


def _time(model: mesa.Model) -> float:
    """Simulated time of the collection (s)."""
    return float(model.time)
