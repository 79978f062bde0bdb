"""Parameter sweeps: a model, a parameter grid and replications, run on any executor.

A sweep is the Cartesian product of its ``grid`` times ``replications``. Each run is the pure,
picklable function :func:`analysis.runner.run_one` (model + parameters + seed -> tidy rows),
handed to an executor (:mod:`analysis.sweep.executors`); each finished run is written at once
(:mod:`analysis.sweep.storage`), runs already on disk are skipped on restart, and a run that
raises becomes a recorded failure. The modules, by job:

- :mod:`~analysis.sweep.spec`: the :class:`Sweep`, grid validation, sweep files (TOML);
- :mod:`~analysis.sweep.design`: sensitivity designs (SALib samples as the sweep's points);
- :mod:`~analysis.sweep.seeding`: run identities and per-run seeds (``SeedSequence``);
- :mod:`~analysis.sweep.storage`: the dataset folder (Parquet);
- :mod:`~analysis.sweep.integrity` and :mod:`~analysis.sweep.membership`: every file in it
  verified, and a run of it only if it is a run of its plan;
- :mod:`~analysis.sweep.folder`: the folder is the sweep's alone (checked and locked);
- :mod:`~analysis.sweep.executors`: serial, local processes, Dask;
- :mod:`~analysis.sweep.execute`: running it all, with progress, resume and Ctrl-C.
"""

from analysis.runner import RunSpec, run_one
from analysis.sweep.execute import execute, run_sweep
from analysis.sweep.executors import EXECUTORS
from analysis.sweep.seeding import plan
from analysis.sweep.spec import Sweep, load_sweep
from analysis.sweep.storage import SweepError, load_results, read_manifest, swept_keys

__all__ = [
    "EXECUTORS",
    "RunSpec",
    "Sweep",
    "SweepError",
    "execute",
    "load_results",
    "load_sweep",
    "plan",
    "read_manifest",
    "run_one",
    "run_sweep",
    "swept_keys",
]
