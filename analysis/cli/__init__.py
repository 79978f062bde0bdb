"""The ``abm`` command line: one sub-command (verb) per module of this package.

Each verb module defines ``VERB`` (its name), ``HELP`` (one line), ``EXAMPLE`` (one command
line), ``add_arguments(parser)`` and ``main(args) -> int``. Errors the project raises on
purpose, any OSError and any bad option are printed as one clear line (no traceback, no usage
block) unless ``--debug`` is given.
"""

import argparse
import atexit
import difflib
import errno
import importlib
import os
import sys
import threading
from typing import NoReturn

from abm.errors import ABMError, ConfigError

__all__ = [
    "main",
    "console",
    "build_parser",
    "one_line",
    "OneLineParser",
    "UsageError",
    "VERB_MODULES",
]

#: Verb modules, in the order ``abm --help`` lists them.
VERB_MODULES = ("run", "sweep", "explore", "calibrate", "report", "fit", "render", "viz")


def _load_verbs() -> list:
    return [importlib.import_module(f"analysis.cli.{name}") for name in VERB_MODULES]


class UsageError(ConfigError):
    """A command line a parser refused, with that parser's ``prog`` (``abm``, ``abm sweep``,
    ...) to name it by.
    """

    def __init__(self, message: str, prog: str = "abm") -> None:
        super().__init__(message)
        self.prog = prog


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose errors are ConfigErrors (one line, naming the option and
    pointing to ``--help``) instead of a usage block and an exit. An option must be given in
    full: argparse would take ``--scouts 3`` for ``--scouts-per-worker 3`` without a word.
    """

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        #: The verbs' own parsers by verb (``abm``'s parser only), for options a verb lacks.
        self.verb_parsers: dict[str, argparse.ArgumentParser] = {}

    def error(self, message: str):
        """Raise the error instead of printing usage and exiting (argparse's contract: never
        return).
        """
        hints = self._close_matches(message)
        raise UsageError(f"{message}{hints} (see {self.prog} --help)", self.prog)

    def _close_matches(self, message: str) -> str:
        """For unrecognised options, the parser's own options they most likely stand for: the
        ones they begin (an abbreviation: "--scouts" -> "--scouts-per-worker"), else the one
        they are most likely misspelt from ("--birdz" -> "--birds"); or nothing.
        """
        prefix = "unrecognized arguments: "
        if not message.startswith(prefix):
            return ""
        known = [option for option in self._option_string_actions if option.startswith("--")]
        hints = []
        for word in message[len(prefix) :].split():
            given = word.split("=", 1)[0]
            if not given.startswith("--"):
                continue
            longer = sorted(option for option in known if option.startswith(given))
            close = longer or difflib.get_close_matches(given, known, 1)
            if close:
                hints.append(f"{' or '.join(close)} for {given}")
        return f"; did you mean {', '.join(hints)}?" if hints else ""


def build_parser() -> OneLineParser:
    """The argument parser with every available verb."""
    verbs = _load_verbs()
    epilog = "examples:\n" + "\n".join(f"  {v.EXAMPLE:<70} # {v.HELP}" for v in verbs)
    parser = OneLineParser(
        prog="abm",
        description="Discrete-event agent-based modelling of robot swarms.",
        epilog=epilog,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--debug", action="store_true", help="show full tracebacks on errors")
    sub = parser.add_subparsers(dest="verb", metavar="VERB")
    for verb in verbs:
        p = sub.add_parser(
            verb.VERB,
            help=verb.HELP,
            description=f"{verb.HELP}\n\nexample:\n  {verb.EXAMPLE}",
            formatter_class=argparse.RawDescriptionHelpFormatter,
        )
        verb.add_arguments(p)
        p.set_defaults(handler=verb.main)
        parser.verb_parsers[verb.VERB] = p
    return parser


def console() -> NoReturn:
    """The ``abm`` console script: :func:`main`, then an exit without the interpreter's teardown.

    When a command has finished, its files are written and closed. The interpreter would then
    free every object of Mesa, pandas, SciPy, numba and matplotlib one by one: 0.4-0.8 s of a
    warm ``abm run flocking`` on a 2.0 GHz Xeon, for nothing the user sees. So, as
    multiprocessing's own child processes do, the command leaves with ``os._exit`` once what
    an ordinary exit runs first has run: every exit handler (logging's flush, a process pool's
    join, a plugin's own) and the flush of stdout and stderr. A thread that is not a daemon
    and still runs gets the ordinary exit, which waits for it; an exception escaping
    :func:`main` (``--debug``) takes the ordinary path too. Callers of :func:`main` (tests,
    scripts) keep the ordinary exit.
    """
    try:
        code = main()
    except SystemExit as exc:  # argparse's --help ends this way
        if not isinstance(exc.code, int | None):
            raise
        code = exc.code or 0
    others = [t for t in threading.enumerate() if t is not threading.main_thread()]
    if any(t.is_alive() and not t.daemon for t in others):
        sys.exit(code)
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe or stream: nothing more can reach it
            pass
    os._exit(code)


def main(argv: list[str] | None = None) -> int:
    """Run one ``abm`` command line (``argv``, default ``sys.argv[1:]``); its exit code."""
    _never_fail_on_encoding(sys.stdout)
    _never_fail_on_encoding(sys.stderr)
    parser = build_parser()
    try:
        args, extras = parser.parse_known_args(argv)
        if extras:  # named by the verb's own parser, which knows the options they misspell
            parser.verb_parsers.get(args.verb, parser).error(
                f"unrecognized arguments: {' '.join(extras)}"
            )
    except ConfigError as exc:  # named by the parser that refused it: abm, or abm VERB
        print(f"{getattr(exc, 'prog', parser.prog)}: error: {one_line(exc)}", file=sys.stderr)
        return 2
    if args.verb is None:
        parser.print_help()
        return 0
    try:
        return int(args.handler(args) or 0)
    except (ABMError, OSError, KeyboardInterrupt) as exc:
        if args.debug:
            raise
        if isinstance(exc, KeyboardInterrupt):
            print("abm: interrupted", file=sys.stderr)
            return 130
        print(f"abm {args.verb}: error: {one_line(exc)}", file=sys.stderr)
        return 2


#: What to do about an operating-system error, by errno.
_OS_ADVICE = {
    errno.ENOSPC: "free some space and run the same command again (finished work is kept)",
    errno.EDQUOT: "free some space and run the same command again (finished work is kept)",
    errno.EROFS: "the folder is read-only: choose a writable place (--out)",
    errno.EACCES: "no permission: choose a place you can write (--out)",
    errno.EPERM: "no permission: choose a place you can write (--out)",
}


def one_line(exc: BaseException, advice: bool = True) -> str:
    """The error as one line; an OSError names its file and (with ``advice``) what to do.

    Line breaks in the message become spaces, and any other character that is not printable
    (a control character or an undecodable byte in a file name) is written as an escape, so
    the line stays one line whatever names it quotes.
    """
    if isinstance(exc, OSError) and exc.strerror:
        where = f" {exc.filename}" if exc.filename else ""
        todo = _OS_ADVICE.get(exc.errno) if advice else None
        text = f"{exc.strerror}:{where}" + (f"; {todo}" if todo else "")
    else:
        text = " ".join(str(exc).split("\n")).strip() or type(exc).__name__
    return "".join(
        c if c.isprintable() else c.encode("unicode_escape", "backslashreplace").decode("ascii")
        for c in text
    )


def _never_fail_on_encoding(stream) -> None:
    """Write what the stream's encoding cannot hold as escapes instead of raising: a path in
    another encoding, or a non-ASCII name on an ASCII terminal, never stops a command after
    its work is done.
    """
    reconfigure = getattr(stream, "reconfigure", None)
    if reconfigure is not None:
        reconfigure(errors="backslashreplace")


if __name__ == "__main__":
    console()
