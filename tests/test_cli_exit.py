"""The ``abm`` console script leaves without the interpreter's teardown, and loses nothing by it.

:func:`analysis.cli.console` ends with ``os._exit`` after the command, which skips the
interpreter's teardown. These tests run it in fresh interpreters and check what an ordinary exit
would have given: the command's exit code, everything it printed (also through a pipe, where
Python buffers stdout), every exit handler registered while it ran, and a thread that is still
working when the command returns.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Runs ``console()`` on ``sys.argv[1:]`` after the code a test passes as ``setup``.
PROBE = """
import atexit, sys, threading, time
from analysis.cli import console
{setup}
sys.argv = ["abm", *sys.argv[1:]]
console()
print("not reached: console() returns only by exiting")
"""


def _console(*argv: str, setup: str = "") -> subprocess.CompletedProcess:
    # stdout buffered as it is for a user's pipe (PYTHONUNBUFFERED would flush every write)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    return subprocess.run(
        [sys.executable, "-c", PROBE.format(setup=setup), *argv],
        capture_output=True, text=True, cwd=ROOT, timeout=120, env=env,
    )  # fmt: skip


@pytest.mark.parametrize(
    ("argv", "code"),
    [(["--help"], 0), (["run", "flocking", "--birds", "-1"], 2), (["no-such-verb"], 2)],
)
def test_the_command_s_exit_code_and_whole_output_survive_the_quick_exit(argv, code):
    done = _console(*argv)
    assert done.returncode == code, done.stderr
    assert "not reached" not in done.stdout
    if code == 0:  # the whole help, to its last line, through a pipe
        assert done.stdout.rstrip().splitlines()[-1].strip().startswith("abm viz")
        assert done.stdout.count("\n") > 10
    else:  # the one-line refusal
        assert len(done.stderr.strip().splitlines()) == 1
        assert "error:" in done.stderr


def test_exit_handlers_registered_before_and_during_the_command_still_run(tmp_path):
    """A plugin's or a library's ``atexit`` handler runs, in the ordinary last-in-first-out
    order, before the process leaves.
    """
    log = tmp_path / "handlers.txt"
    setup = f"""
log = open({str(log)!r}, "w")
atexit.register(lambda: log.write("first registered, runs last\\n") and log.close())
atexit.register(lambda: log.write("second registered, runs first\\n") and log.flush())
"""
    done = _console("--help", setup=setup)
    assert done.returncode == 0, done.stderr
    assert log.read_text().splitlines() == [
        "second registered, runs first",
        "first registered, runs last",
    ]


def test_a_thread_still_working_when_the_command_returns_is_waited_for(tmp_path):
    """A non-daemon thread gets the ordinary exit, which joins it: its work is not cut off."""
    done_file = tmp_path / "thread.txt"
    setup = f"""
def work():
    time.sleep(0.5)
    with open({str(done_file)!r}, "w") as f:
        f.write("finished")
threading.Thread(target=work).start()
"""
    done = _console("run", "flocking", "--birds", "-1", setup=setup)
    assert done.returncode == 2, done.stderr
    assert done_file.read_text() == "finished"


def test_the_interpreter_s_teardown_is_skipped_after_help_and_after_a_refusal(tmp_path):
    """What makes the exit quick: objects still alive at the end are not freed one by one (an
    ordinary exit would run this finaliser while it clears the modules).
    """
    for argv in (["--help"], ["run", "flocking", "--help"], ["run", "flocking", "--birds", "0"]):
        freed = tmp_path / "freed.txt"
        setup = f"""
import pathlib
class Sentinel:
    def __del__(self, touch=pathlib.Path({str(freed)!r}).touch):  # bound now: teardown
        touch()                                                 # clears the builtins
kept_until_the_end = Sentinel()
"""
        done = _console(*argv, setup=setup)
        assert done.returncode in (0, 2), done.stderr
        assert not freed.exists(), argv
