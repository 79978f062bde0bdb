"""Memory budget: refuse a map whose model would not fit in this machine's memory, up front.

A model on a bitmap map allocates several arrays per map pixel (the arena's grids, coverage
rasters, pheromone fields and their visibility tables, precomputed force fields), so a small
file can ask for gigabytes: a 62 KB PNG of 7000 x 7000 pixels made the stigmergy model grow
past 5.6 GB without a word. The map loaders (:func:`models.environments.load_map`,
:meth:`abm.arena.Arena.from_bitmap`) therefore read only a file's header, ask the model what
it will allocate per pixel, and compare the sum with a budget tied to the machine before
decoding a single pixel:

- the budget is :data:`SHARE` of the memory the kernel reports available now
  (``MemAvailable`` in ``/proc/meminfo``; elsewhere ``os.sysconf``'s free physical pages);
- the environment variable ``ABM_MEMORY_LIMIT`` (bytes, or with a K/M/G/T suffix: ``"4G"``)
  replaces it, e.g. for a machine whose other work will free memory, or to pin it in tests.

The estimates count the arrays' own bytes (numpy's, measured with ``tracemalloc``), not
Python's baseline, so a refused map would certainly not have fitted in the budget.
"""

import os
import re
from collections.abc import Mapping
from pathlib import Path

from abm.errors import ConfigError, MapError

__all__ = ["ENV", "SHARE", "check_map_memory", "format_bytes", "memory_budget"]

#: Environment variable that sets the budget (bytes; K, M, G, T suffixes are powers of 1024).
ENV = "ABM_MEMORY_LIMIT"
#: Share of the available memory one model may plan to use (ours): the rest is left for Python
#: itself, the temporaries the estimates leave out, and the other workers of a sweep.
SHARE = 0.5

_UNITS = {"": 1, "K": 1024, "M": 1024**2, "G": 1024**3, "T": 1024**4}


def memory_budget() -> tuple[float, str]:
    """The bytes one model may plan to allocate, and where the figure comes from.

    Returns:
        ``(bytes, how)``: ``how`` reads e.g. "half of the 21.4 GB available now" or
        "ABM_MEMORY_LIMIT=4G"; ``bytes`` is ``inf`` where the machine reports nothing.

    Raises:
        ConfigError: ``ABM_MEMORY_LIMIT`` is set to something that is not a size.

    """
    text = os.environ.get(ENV, "").strip()
    if text:
        match = re.fullmatch(r"(\d+(?:\.\d+)?)\s*([KMGT]?)B?", text.upper())
        if match is None:
            raise ConfigError(
                f"{ENV} must be a size in bytes, optionally with a K, M, G or T suffix "
                f"(e.g. 4G), got {text!r}"
            )
        return float(match.group(1)) * _UNITS[match.group(2)], f"{ENV}={text}"
    available = _available()
    if available is None:
        return float("inf"), "this machine reports no available memory"
    share = "half" if SHARE == 0.5 else f"{SHARE:g}"
    return SHARE * available, f"{share} of the {format_bytes(available)} available now"


def check_map_memory(map_name: str, shape: tuple[int, int], parts: Mapping[str, float]) -> None:
    """Refuse a map whose model would need more than :func:`memory_budget` allows.

    Args:
        map_name: how the user named the map (a path or a name), for the message.
        shape: ``(rows, cols)`` of the map in pixels.
        parts: what the model would allocate for this map (bytes), by part ("arena",
            "coverage raster", ...).

    Raises:
        MapError: "this 7000 x 7000 map would need ~13.4 GB (arena 2.9 GB, ...); this machine
            allows 10.7 GB (half of the 21.4 GB available now); ...".

    """
    need = float(sum(parts.values()))
    budget, how = memory_budget()
    if need <= budget:
        return
    rows, cols = shape
    detail = ", ".join(
        f"{name} {format_bytes(size)}"
        for name, size in sorted(parts.items(), key=lambda kv: -kv[1])
        if size >= 0.01 * need
    )
    raise MapError(
        f"map {map_name!r}: this {cols} x {rows} pixel map would need ~{format_bytes(need)} "
        f"({detail}); this machine allows {format_bytes(budget)} ({how}). Use a smaller or "
        f"coarser map (fewer pixels), or set {ENV} (e.g. {ENV}=32G) if more memory will be free"
    )


def format_bytes(size: float) -> str:
    """``size`` bytes as "1.5 GB" / "320 MB" / "12 KB" (powers of 1024)."""
    for unit in ("TB", "GB", "MB", "KB"):
        scale = _UNITS[unit[0]]
        if size >= scale:
            return f"{size / scale:.3g} {unit}"
    return f"{size:.0f} B"


def _available() -> float | None:
    """Bytes of memory available to new work now, or None where the system does not say: the
    machine's, or less where a cgroup (a container's limit) leaves less.
    """
    machine = None
    meminfo = Path("/proc/meminfo")
    if meminfo.exists():
        for line in meminfo.read_text().splitlines():
            if line.startswith("MemAvailable:"):
                machine = float(line.split()[1]) * 1024
    if machine is None:
        try:
            machine = float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (AttributeError, ValueError, OSError):
            return None
    group = Path("/sys/fs/cgroup")
    try:
        limit = (group / "memory.max").read_text().strip()
        used = float((group / "memory.current").read_text())
    except (OSError, ValueError):
        return machine
    return machine if limit == "max" else min(machine, max(0.0, float(limit) - used))
