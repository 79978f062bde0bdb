"""The example model of ``docs/adding-a-model.md``, written out from the page itself, passes
every verb: the page is what a newcomer copies, so the page is what is tested.

Each code block of the example opens with the file it belongs in (``# models/walker/x.py``);
the test writes those blocks into a package ``walker`` of a temporary folder and uses the
model as ``walker.model:WalkerModel``.
"""

import os
import re
import sys
from pathlib import Path

import pytest

from abm import registry
from analysis.cli import main

DOCS = Path(__file__).resolve().parent.parent / "docs" / "adding-a-model.md"
TARGET = "walker.model:WalkerModel"
#: A code block of the example: its first line names its file.
BLOCK = re.compile(r"```python\n# models/walker/(\w+\.py)\n(.*?)```", re.DOTALL)


def example_files(text: str) -> dict[str, str]:
    """File name -> source of each of the example's code blocks in ``text``."""
    return {name: body for name, body in BLOCK.findall(text)}


@pytest.fixture
def walker(tmp_path, monkeypatch) -> Path:
    """The example written out as the package ``walker`` (importable here and in workers)."""
    files = example_files(DOCS.read_text())
    assert set(files) == {"params.py", "agents.py", "model.py", "published.py"}
    package = tmp_path / "site" / "walker"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    for name, body in files.items():
        (package / name).write_text(body)
    site = str(package.parent)
    monkeypatch.syspath_prepend(site)
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([site, *sys.path]))
    monkeypatch.chdir(tmp_path)
    yield tmp_path
    for module in [m for m in sys.modules if m == "walker" or m.startswith("walker.")]:
        del sys.modules[module]


def test_the_example_imports_keeps_the_contract_and_runs(walker):
    cls = registry.model_class(TARGET)
    model = cls(seed=1, walkers=3, launch_period=1.0, rest_rate=0.5, time_limit=60.0).run()
    summary = model.summary()
    assert summary["resting"] + model.recorder.counts["walking"] == 3
    assert summary["end_reason"] in ("all resting", "time limit")


def test_the_example_robots_are_walker_agents_running_their_own_walk(walker):
    """The page's shape: the robots are the Walker class of agents.py, Mesa's AgentSet is
    their index, and each rests at the end of its own behaviour, Walker.walk."""
    from walker.agents import Walker

    assert "def walk(self)" in example_files(DOCS.read_text())["agents.py"]
    cls = registry.model_class(TARGET)
    model = cls(seed=3, walkers=5, launch_period=1.0, rest_rate=0.2, time_limit=600.0)
    model.run()
    walkers = model.agents_by_type[Walker]
    assert set(model.agents_by_type) == {Walker} and len(walkers) == 5
    assert model.end_reason == "all resting"
    assert all(w.state == "resting" and not w.process.is_alive for w in walkers)


def _wrote(out: str) -> list[Path]:
    return [Path(line[6:].strip()) for line in out.splitlines() if line.startswith("wrote ")]


@pytest.mark.slow
def test_the_example_passes_every_verb(walker, capsys):
    small = {"walkers": 4, "launch_period": 2.0, "time_limit": 60.0}
    flags = [w for k, v in small.items() for w in (f"--{k.replace('_', '-')}", str(v))]
    # abm run, then abm render of what it wrote
    assert main(["run", TARGET, *flags, "--seed", "2", "--out", "run"]) == 0
    assert all(p.exists() for p in _wrote(capsys.readouterr().out))
    assert main(["render", "run", "--no-gif"]) == 0
    assert all(p.exists() for p in _wrote(capsys.readouterr().out))
    # abm sweep + abm report (the published numbers are judged or said not comparable)
    grid = "".join(f"{k} = [{v!r}]\n" for k, v in small.items())
    Path("walker.toml").write_text(f'model = "{TARGET}"\nseed = 1\nreplications = 2\n'
                                   f"[grid]\n{grid}")  # fmt: skip
    assert main(["sweep", "walker.toml", "--executor", "serial", "--out", "sweep"]) == 0
    capsys.readouterr()
    assert main(["report", "sweep"]) == 0
    assert all(p.exists() for p in _wrote(capsys.readouterr().out))
    assert "Published numbers beside ours" in Path("sweep/report.html").read_text()
    # abm fit: the recurrence on walking/resting; the launch period and the walkers it reads
    # are parameters left at their defaults, so no run's row holds them: read from the params
    args = ["fit", TARGET, "--set", "time_limit=60", "--runs", "2", "--workers", "1"]
    assert main([*args, "--out", "fit"]) == 0
    printed = capsys.readouterr().out
    assert "walking" in printed.splitlines()[0] and "resting_share_0" in printed
    assert Path("fit/fit_report.html").is_file()
