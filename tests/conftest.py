"""Shared fixtures: the tiny model of ``tiny_model.py`` registered as an installed package
would register it, through the ``swarm_abm.models`` entry-point group."""

import os
import sys
from pathlib import Path

import pytest
from hypothesis import settings

from abm import registry

TESTS = Path(__file__).resolve().parent

# No per-example deadline for property tests: the first example of a test often loads numba
# (0.3 s of start-up before any cached kernel runs) or compiles, so a test run alone failed as
# "flaky" on its first example (tests/test_kinematics.py's angle wrap, 355 ms against 200 ms).
settings.register_profile("project", deadline=None)
settings.load_profile("project")


@pytest.fixture(scope="session")
def tiny_package(tmp_path_factory) -> Path:
    """A folder on sys.path with the metadata of a package whose entry point adds "tiny".

    Returns the folder; subprocesses find the model with it (and this folder) on PYTHONPATH.
    """
    site = tmp_path_factory.mktemp("site")
    info = site / "tiny_models-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: tiny-models\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(
        f"[{registry.ENTRY_POINT_GROUP}]\ntiny = tiny_model:TinyModel\n"
    )
    sys.path.insert(0, str(site))
    before = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(site), str(TESTS), before]))
    registry.refresh()
    yield site
    sys.path.remove(str(site))
    if before is None:
        os.environ.pop("PYTHONPATH")
    else:
        os.environ["PYTHONPATH"] = before
    registry.refresh()


def pytest_terminal_summary(terminalreporter) -> None:
    """After the run: how many cases each fuzz target tried (tests/fuzzing.py)."""
    fuzzing = sys.modules.get("fuzzing")
    if fuzzing is not None and fuzzing.COUNTS:
        terminalreporter.section("fuzz cases tried")
        for line in fuzzing.summary():
            terminalreporter.write_line(line)
