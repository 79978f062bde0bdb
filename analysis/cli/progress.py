"""A progress line on stderr for a single run that takes longer than a few seconds.

The line shows what a swarm run's user watches: simulated time against the time limit, robots
per state, events logged so far and the speed in simulated seconds per wall-clock second, with
tqdm's elapsed and remaining time (the bar Mesa's ``batch_run`` and ``abm sweep`` show too).

It is driven from outside the model: a SimPy process added to the model's clock wakes once per
``step_duration`` of simulated time (the model's Mesa step) and reads only public state
(``env.now``, the recorder's counts). It draws nothing from the model's random generator and
only adds wake-ups of its own to the queue, so the run is the same event for event; a wake-up
costs one clock read, and the line is redrawn at most a few times a second. Nothing appears
for a run that ends within ``delay`` seconds of wall time, so short runs and tests stay quiet.
"""

import math
import sys
import time
from typing import TextIO

from tqdm import tqdm

__all__ = ["DELAY", "RunProgress"]

#: Wall-clock seconds before the line appears.
DELAY = 3.0

#: Least wall-clock time between two redraws (s).
_REDRAW = 0.5


class RunProgress:
    """Watches one model's run; draws the progress line once the run is slow enough to need one.

    Use as a context manager around ``model.run()``: leaving it closes the line.

    Args:
        model: a SwarmModel not yet run.
        delay: wall-clock seconds before the line appears.
        file: where the line goes (stderr by default: stdout keeps only the results).

    """

    def __init__(self, model, delay: float = DELAY, file: TextIO | None = None) -> None:
        self.model = model
        limit = float(model.time_limit)
        self._bar = tqdm(
            total=limit if math.isfinite(limit) else None,
            delay=delay,
            file=file if file is not None else sys.stderr,
            bar_format="{percentage:3.0f}%|{bar:16}| {desc} [{elapsed}<{remaining}]",
            mininterval=0.0,  # _watch already redraws at most every _REDRAW seconds
        )
        self._start = time.monotonic()
        self._last = self._start
        self._ran = 0.0
        model.env.process(self._watch(float(model.step_duration)))

    def __enter__(self) -> "RunProgress":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Draw the final state (if the line is shown) and end the line."""
        wall = time.monotonic()
        self._draw(wall)
        self._bar.close()
        self._ran = wall - self._start

    @property
    def shown(self) -> bool:
        """Whether the run (until :meth:`close`) lasted long enough for the line to appear."""
        return self._ran >= self._bar.delay

    def line(self) -> str:
        """The text after the bar: simulated time, robots per state, events, speed."""
        model = self.model
        now = float(model.env.now)
        counts = model.recorder.counts
        robots = sum(counts.values())
        per_state = ", ".join(f"{state} {n}" for state, n in counts.items() if n)
        wall = time.monotonic() - self._start
        speed = f", {now / wall:,.0f}x real time" if wall > 0 else ""
        limit = "" if self._bar.total is None else f"/{self._bar.total:,.0f}"
        return (
            f"t {now:,.0f}{limit} s, {robots} robots"
            + (f" ({per_state})" if per_state else "")
            + f", {model.recorder.logged:,} events{speed}"
        )

    def _watch(self, every: float):
        env = self.model.env
        while True:
            yield env.timeout(every)
            wall = time.monotonic()
            if wall - self._last >= _REDRAW:
                self._draw(wall)

    def _draw(self, wall: float) -> None:
        self._last = wall
        now = min(float(self.model.env.now), self._bar.total or math.inf)
        self._bar.set_description_str(self.line(), refresh=False)
        self._bar.update(now - self._bar.n)  # tqdm draws it once ``delay`` has passed
