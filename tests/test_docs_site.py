"""The documentation site builds with ``mkdocs build --strict``: no broken link or anchor, no page
left out of the navigation, no docstring the API reference cannot read.

`make test-slow` and `make test-all` install the ``docs`` extra first, so CI runs this on a fresh
machine; without the tools (a plain ``pytest`` in a venv made by ``make venv``) it is skipped.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

pytestmark = pytest.mark.slow


def build(site: Path, config: Path = ROOT / "mkdocs.yml") -> subprocess.CompletedProcess:
    """Run the strict build of ``config`` into ``site``; return the finished process."""
    pytest.importorskip("mkdocs", reason="the docs extra is not installed (make docs-setup)")
    pytest.importorskip("mkdocstrings_handlers.python")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "DISABLE_MKDOCS_2_WARNING": "true"}
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(config), "-d", str(site)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_the_site_builds_strictly_with_the_api_reference(tmp_path):
    done = build(tmp_path / "site")
    assert done.returncode == 0, done.stderr[-4000:]
    assert "WARNING" not in done.stderr, done.stderr[-4000:]
    site = tmp_path / "site"
    for page in ("getting-started", "reproduction", "performance", "history", "adding-a-model"):
        assert (site / page / "index.html").is_file(), page
    # The reference is generated from the packages: a model's class and its docstring are there.
    api = (site / "api" / "models" / "beacon_explorer" / "index.html").read_text(encoding="utf-8")
    assert "BeaconExplorerModel" in api
    # Sphinx roles in docstrings show as code, not as literal ":class:" text
    network = (site / "api" / "abm" / "comms" / "network" / "index.html").read_text("utf-8")
    assert ":class:<code>" not in network and "<code>Shadowing</code>" in network
    # The README's pictures and the models' READMEs come along, with links that work in the site.
    assert (site / "images" / "run.png").is_file()
    start = (site / "getting-started" / "index.html").read_text(encoding="utf-8")
    assert 'src="../images/run.png"' in start
    assert (site / "repo" / "models" / "hierarchy" / "index.html").is_file()
