"""The recorder: an event log and state-count time series, as tidy pandas DataFrames."""

from collections.abc import Iterable, Mapping, Sequence

import numpy as np
import pandas as pd
import simpy

__all__ = ["Recorder"]


class Recorder:
    """Collects what happens during a run.

    ``log`` appends one event (time, kind, robot, extra fields); ``move`` keeps the number of
    robots in each state and appends a row to the state series whenever a count changes;
    ``sample`` appends a row of the model's own measurements (a time series of metrics).

    Kinds of event that can happen millions of times in a crowded run (collisions: 41.5 M
    rows, 5.7 GB, in a 2,000-robot run) may have a row limit: past it, events of that kind are
    counted (:attr:`dropped`) but not kept, and one ``rows_capped`` event (with the ``kind``
    and its ``limit``) marks in the log where the rows stop. Whoever counts the events (the
    model's collision counters) counts them all the same.

    Args:
        env: the clock.
        states: the robot states counted (columns of :meth:`state_counts`).
        row_limits: event kind -> most rows kept of it (None: all).

    """

    def __init__(
        self,
        env: simpy.Environment,
        states: Iterable[str],
        row_limits: Mapping[str, int | None] | None = None,
    ) -> None:
        self.env = env
        self.states = tuple(states)
        self.counts = dict.fromkeys(self.states, 0)
        self.row_limits = {k: v for k, v in (row_limits or {}).items() if v is not None}
        #: Event kind -> events not kept past its row limit.
        self.dropped: dict[str, int] = {}
        self._kept = dict.fromkeys(self.row_limits, 0)
        self._events: list[dict] = []
        self._series: list[tuple] = []
        self._samples: list[dict] = []
        self._trace = _Trace(self.states)
        #: State changes recorded so far (:meth:`move` calls): whoever keeps the robots'
        #: states knows they are unchanged while this is.
        self.moves = 0

    @property
    def logged(self) -> int:
        """Events logged so far (a progress line reads it while the run goes)."""
        return len(self._events)

    def log(self, kind: str, robot: int | None = None, **fields: object) -> None:
        """Append an event at ``env.now`` (or count it, past its kind's row limit)."""
        if kind in self._kept:
            limit = self.row_limits[kind]
            if self._kept[kind] >= limit:
                if kind not in self.dropped:
                    self.dropped[kind] = 0
                    self._events.append(
                        {
                            "time": self.env.now,
                            "event": "rows_capped",
                            "robot": None,
                            "kind": kind,
                            "limit": limit,
                        }  # fmt: skip
                    )
                self.dropped[kind] += 1
                return
            self._kept[kind] += 1
        self._events.append({"time": self.env.now, "event": kind, "robot": robot, **fields})

    def move(self, old: str | None, new: str | None) -> None:
        """One robot changed state from ``old`` (None when it appears) to ``new`` (None when
        it leaves the model).
        """
        self.moves += 1
        if old is not None:
            self.counts[old] -= 1
        if new is not None:
            self.counts[new] += 1
        row = (self.env.now, *self.counts.values())  # keys: the states, in their order
        if self._series and self._series[-1][0] == self.env.now:
            self._series[-1] = row
        else:
            self._series.append(row)

    def entered(self, state: str, robots: list[int]) -> None:
        """The ``robots`` joined the model in ``state`` at ``env.now``: the ``state`` events and
        the counts of a :meth:`move` from None and a ``log("state", ...)`` for each in turn.
        """
        if not robots:
            return
        if "state" in self._kept:  # a capped kind: counted one by one
            for robot in robots:
                self.log("state", robot, state=state)
        else:
            now = self.env.now
            self._events.extend(
                {"time": now, "event": "state", "robot": robot, "state": state} for robot in robots
            )
        self.counts[state] += len(robots) - 1
        self.move(None, state)

    def sample(self, **values: float) -> None:
        """Record the model's measurements at ``env.now`` (one row of :meth:`samples`)."""
        self._samples.append({"time": self.env.now, **values})

    def samples(self) -> pd.DataFrame:
        """The measurements recorded with :meth:`sample`, one row per sample (``time`` first)."""
        return pd.DataFrame(self._samples)

    def snapshot(
        self,
        robots: np.ndarray,
        positions: np.ndarray,
        states: Sequence[str] | np.ndarray,
        comm: Sequence[bool] | np.ndarray,
    ) -> None:
        """Record where every robot is, what it is and whether it is a comm node at ``env.now``.

        ``states`` are the robots' state names, or their codes from :meth:`state_codes`: a
        caller that samples the same robots again and again keeps the codes (and passes the
        same arrays while nothing changed, which the recorder then does not compare again).
        """
        self._trace.add(self.env.now, robots, positions, states, comm)

    def state_codes(self, states: Iterable[str]) -> np.ndarray:
        """The codes of ``states`` (names of this recorder's states) that :meth:`snapshot`
        takes in place of the names.
        """
        return self._trace.codes(states)

    def positions(self) -> pd.DataFrame:
        """Sampled positions: one row per robot and sample (time, robot, x, y, state, comm)."""
        return self._trace.frame()

    def events(self) -> pd.DataFrame:
        """The event log, one row per event, in time order."""
        return pd.DataFrame(self._events)

    def state_counts(self) -> pd.DataFrame:
        """Robots per state after every change: a ``time`` column and one column per state."""
        return pd.DataFrame(self._series, columns=["time", *self.states])


class _Trace:
    """The sampled positions, stored as changes: a sample keeps only the robots whose
    position, state or comm membership differ from their previous sample.

    Most robots of a large swarm hang still (beacons) or wait (on the ground) between two
    samples: a 10,000-robot beacon/explorer run samples 3e8 robot-seconds, 11 GB when every
    row was kept, of which a few per cent move. :meth:`frame` gives every row back, as the
    full samples would.

    Args:
        states: the robot states, in the order their codes number them.

    """

    def __init__(self, states: Sequence[str]) -> None:
        self._states = tuple(states)
        self._code = {s: k for k, s in enumerate(self._states)}
        #: per sample: (time, robots, changed rows, their positions, state codes, comm)
        self._samples: list[
            tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
        ] = []
        self._last: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None

    def codes(self, states: Iterable[str]) -> np.ndarray:
        """The state codes of ``states`` (names)."""
        return np.array(list(map(self._code.__getitem__, states)), dtype=np.int8)

    def add(
        self,
        time: float,
        robots: np.ndarray,
        positions: np.ndarray,
        states: Sequence[str] | np.ndarray,
        comm: Sequence[bool] | np.ndarray,
    ) -> None:
        """Keep one sample (the rows that changed since the previous one); ``states`` are
        names or, as an int8 array, their codes (:meth:`codes`).
        """
        robots = np.asarray(robots, dtype=np.int64)
        positions = np.array(positions, dtype=float).reshape(-1, 2)
        if isinstance(states, np.ndarray) and states.dtype == np.int8:
            codes = states
        else:
            codes = self.codes(states)
        comm = np.asarray(comm, dtype=bool)
        last = self._last
        if last is not None and (robots is last[0] or np.array_equal(last[0], robots)):
            robots = last[0]  # the same robots in the same rows: one array for both samples
            # a row moved when x or y differs, compared as one complex number per row (the
            # same verdicts as comparing the two floats, NaN and -0.0 included)
            moved = positions.view(np.complex128).ravel() != last[1].view(np.complex128).ravel()
            if codes is not last[2]:  # the same array: the caller kept the codes unchanged
                moved |= codes != last[2]
            if comm is not last[3]:
                moved |= comm != last[3]
            changed = np.flatnonzero(moved)
        else:
            changed = np.arange(len(robots))
        self._last = (robots, positions, codes, comm)
        if len(changed) == len(robots):  # every row: no fancy indexing; positions is our own
            # copy already, codes and comm may be arrays the caller keeps, so they are copied
            self._samples.append((time, robots, changed, positions, codes.copy(), comm.copy()))
        else:
            self._samples.append(
                (time, robots, changed, positions[changed], codes[changed], comm[changed])
            )

    def frame(self) -> pd.DataFrame:
        """One row per robot and sample (time, robot, x, y, state, comm)."""
        if not self._samples:
            return pd.DataFrame(columns=["time", "robot", "x", "y", "state", "comm"])
        sizes = [len(sample[1]) for sample in self._samples]
        total = sum(sizes)
        xy = np.empty((total, 2))
        codes = np.empty(total, dtype=np.int8)
        comm = np.empty(total, dtype=bool)
        start = 0
        for (_time, _robots, changed, where, code, linked), size in zip(
            self._samples, sizes, strict=True
        ):
            rows = slice(start, start + size)
            if len(changed) < size:  # the rest as in the previous sample (the same robots)
                xy[rows] = xy[start - size : start]
                codes[rows] = codes[start - size : start]
                comm[rows] = comm[start - size : start]
            xy[start + changed] = where
            codes[start + changed] = code
            comm[start + changed] = linked
            start += size
        return pd.DataFrame(
            {
                "time": np.repeat([sample[0] for sample in self._samples], sizes),
                "robot": np.concatenate([sample[1] for sample in self._samples]),
                "x": xy[:, 0],
                "y": xy[:, 1],
                "state": np.array(self._states, dtype=object)[codes].tolist(),
                "comm": comm,
            }
        )
