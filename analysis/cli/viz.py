"""``abm viz MODEL``: serve any model's SolaraViz page (arena, robots, links, coverage, live
plots): the page in the model's ``APP`` module, or a default page with sliders for its
parameters.
"""

import argparse
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

from abm.errors import ABMError

VERB = "viz"
HELP = "open a model in the browser: arena, robots, comm links, coverage, sliders, live plots"
EXAMPLE = "abm viz beacon-explorer --port 8765"

#: Seconds to wait for the server to answer before giving up.
START_TIMEOUT = 60.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm viz``."""
    from abm.registry import model_names

    parser.add_argument("model", help=f"the model: {', '.join(model_names())} (or module:Class)")
    parser.add_argument("--port", type=int, default=8765, help="TCP port (default 8765)")
    parser.add_argument(
        "--host", default="localhost", help="interface to listen on (default localhost)"
    )


def check_viz_installed() -> None:
    """Raise ABMError with the fix unless Solara and its offline browser files are there."""
    try:
        import solara.server.settings as settings
    except ImportError as exc:
        raise ABMError(
            "the viz extra is not installed: run `.venv/bin/pip install -e '.[viz]'` "
            "and `sh scripts/solara_assets.sh`"
        ) from exc
    cache = Path(settings.assets.proxy_cache_dir)
    if not any(cache.glob("@widgetti/solara-vuetify-app@*")):
        print(
            f"abm viz: warning: Solara's browser files are not in {cache}; without internet the "
            "page stays blank. Fill the cache with `sh scripts/solara_assets.sh`.",
            file=sys.stderr,
        )


def server_command(model: str, host: str, port: int) -> tuple[list[str], dict]:
    """The command line and environment that serve ``model``'s page.

    The server process finds the model by ``module:Class``, so a model registered at run time
    (or only importable from the current folder) is served as well.
    """
    from abm.registry import target_of
    from abm.viz.app import ENV_VAR

    target = target_of(model)
    command = [
        sys.executable, "-m", "solara", "run", "abm.viz.app",
        "--host", host, "--port", str(port),
        "--no-open", "--production", "--no-check-version", "--log-level", "warning",
    ]  # fmt: skip
    path = os.pathsep.join(filter(None, [os.getcwd(), os.environ.get("PYTHONPATH")]))
    env = {
        **os.environ,
        ENV_VAR: target,
        "PYTHONPATH": path,
        "SOLARA_TELEMETRY_MIXPANEL_ENABLE": "False",
    }
    return command, env


def wait_for_port(host: str, port: int, process: subprocess.Popen, timeout: float) -> None:
    """Wait until ``host:port`` accepts connections; raise ABMError if the server died."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise ABMError(f"the Solara server exited with code {process.returncode}")
        try:
            with socket.create_connection((host, port), timeout=0.5):
                return
        except OSError:
            time.sleep(0.2)
    raise ABMError(f"the Solara server did not answer on {host}:{port} within {timeout:g} s")


def _port_in_use(host: str, port: int) -> bool:
    with socket.socket() as sock:
        sock.settimeout(0.5)
        return sock.connect_ex((host, port)) == 0


def main(args: argparse.Namespace) -> int:
    """Start the server, print the address, serve until Ctrl+C."""
    from abm.registry import target_of

    target_of(args.model)  # bad input is named before the environment is looked at
    if not 0 < args.port < 65536:
        raise ABMError(f"--port must be in [1, 65535], got {args.port}")
    check_viz_installed()
    command, env = server_command(args.model, args.host, args.port)
    if _port_in_use(args.host, args.port):
        raise ABMError(f"port {args.port} is already in use; choose another with --port")
    process = subprocess.Popen(command, env=env)
    # A plain `kill` (SIGTERM) must stop the server too, not orphan it.
    signal.signal(signal.SIGTERM, lambda _signum, _frame: sys.exit(128 + signal.SIGTERM))
    try:
        wait_for_port(args.host, args.port, process, START_TIMEOUT)
        print(f"serving the {args.model} page at http://{args.host}:{args.port}/", flush=True)
        print("open it in a browser; press Ctrl+C to stop", flush=True)
        return process.wait()
    finally:
        if process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
