"""Draws a run's PNG in a process of its own, started before the run, so that loading
matplotlib (most of a second) overlaps the run's own imports and the run on another core.

The parent describes the picture as plain data (:class:`abm.scene.Picture`, which pickles) and
sends it over the child's stdin; the child, started as ``python -m abm.png_process``, has
imported the drawing code meanwhile, draws the picture with :func:`abm.draw.save_picture` and
exits 0. Anything else (no process could start, the child died, a picture it could not draw)
makes the parent draw the picture itself, so the PNG is the same either way and an error in
the drawing is raised where the caller sees it.
"""

import os
import pickle
import subprocess
import sys
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # not at run time: abm.scene loads numba, which would delay the child
    from abm.scene import Picture

__all__ = ["PngProcess"]

#: Seconds the parent waits for the child's PNG before drawing it itself.
PATIENCE = 300.0


class PngProcess:
    """A child process that will draw one :class:`~abm.scene.Picture`; use it as a context
    manager, so the child never outlives the command (it is killed if no picture came).
    """

    def __init__(self) -> None:
        # The child finds the modules the parent does (a checkout on sys.path, a test's
        # packages), and not whatever the working folder holds (-P).
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
        try:
            self._child: subprocess.Popen | None = subprocess.Popen(
                [sys.executable, "-P", "-m", "abm.png_process"],
                stdin=subprocess.PIPE,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE,
                env=env,
            )
        except OSError:
            self._child = None

    def __enter__(self) -> "PngProcess":
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def save(self, picture: "Picture", path: str | Path) -> Path:
        """Save ``picture`` as a PNG at ``path`` (drawn by the child, or here if it cannot)."""
        path = Path(path)
        if self._drawn_by_child(picture, path):
            return path
        from abm.draw import save_picture

        return save_picture(picture, path)

    def close(self) -> None:
        """Stop the child if it still waits for a picture."""
        if self._child is not None and self._child.poll() is None:
            self._child.kill()
            self._child.wait()
        self._child = None

    def _drawn_by_child(self, picture: "Picture", path: Path) -> bool:
        """Whether the child drew ``picture`` to ``path``; its warnings go to our stderr."""
        child, self._child = self._child, None
        if child is None:
            return False
        job = pickle.dumps((picture, str(path.absolute())), protocol=pickle.HIGHEST_PROTOCOL)
        try:
            _, err = child.communicate(job, timeout=PATIENCE)
        except (OSError, subprocess.TimeoutExpired):
            child.kill()
            child.wait()
            return False
        if child.returncode != 0:
            return False
        if err:
            sys.stderr.write(err.decode(errors="replace"))
        return path.is_file()


def _serve() -> None:
    """The child: load the drawing code, then draw the one picture that comes on stdin.

    Ends with ``os._exit`` once the PNG is written and stderr flushed: the parent waits for
    this process, and freeing matplotlib's objects one by one on the way out would only delay
    it. A picture that cannot be drawn raises, which exits non-zero the ordinary way.
    """
    from abm.draw import save_picture

    try:
        picture, path = pickle.load(sys.stdin.buffer)
    except EOFError:  # the parent needed no picture after all
        picture = None
    if picture is not None:
        save_picture(picture, path)
    sys.stderr.flush()
    os._exit(0)


if __name__ == "__main__":
    _serve()
