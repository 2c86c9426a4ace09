"""The `rcl` command: run and check RCL programs.

    rcl run FILE        exit 0 ok, 1 runtime error, 2 static errors, 130 interrupted
    rcl check FILE...   exit 0 clean, 2 static errors

Only this module and the REPL print diagnostics.
"""
from __future__ import annotations

import argparse
import os
import signal
import sys
from typing import Optional, Sequence

from . import __version__
from .errors import RclCancelled, RclRuntimeError, RclStaticError

EXIT_OK, EXIT_RUNTIME, EXIT_STATIC, EXIT_INTERRUPTED = 0, 1, 2, 130


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return EXIT_STATIC
    return args.handler(args)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="rcl", description="RCL, the Robot Control Language.")
    p.add_argument("--version", action="version", version=f"rcl {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    run = sub.add_parser("run", help="check and run an .rcl program")
    run.add_argument("file", metavar="FILE")
    run.add_argument("--step-budget", type=_positive_int, metavar="N",
                     help="stop after N loop iterations and routine calls")
    run.set_defaults(handler=_run)
    check = sub.add_parser("check", help="check .rcl programs without running them")
    check.add_argument("files", nargs="+", metavar="FILE")
    check.set_defaults(handler=_check)
    return p


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if n <= 0:
        raise argparse.ArgumentTypeError(f"must be positive: {n}")
    return n


def _run(args) -> int:
    from .session import FileNotReadable, RclInternalError, Session

    session = Session(step_budget=args.step_budget)
    try:
        session.run_file(args.file)
    except FileNotReadable as e:
        return _fail(f"rcl: error: {e}", EXIT_STATIC)
    except RclStaticError as e:
        return _report_static(e)
    except RclRuntimeError as e:
        return _fail(e.render(), EXIT_RUNTIME)
    except RclCancelled as e:
        code = EXIT_INTERRUPTED if e.by_user else EXIT_RUNTIME
        return _fail(e.render() + "\nthe robot was halted", code)
    except RclInternalError as e:
        if os.environ.get("RCL_DEBUG"):
            raise
        return _fail(f"rcl: {e} (a fault in RCL itself; set RCL_DEBUG=1 to see where)", EXIT_RUNTIME)
    finally:
        _flush()
    return EXIT_OK


def _check(args) -> int:
    from .session import FileNotReadable, Session

    status = EXIT_OK
    for path in args.files:
        try:
            diagnostics = Session().check_file(path)
        except FileNotReadable as e:
            print(f"rcl: error: {e}", file=sys.stderr)
            status = EXIT_STATIC
            continue
        if diagnostics:
            _report_static(RclStaticError(diagnostics))
            status = EXIT_STATIC
    return status


def _report_static(e: RclStaticError) -> int:
    for d in e.diagnostics:
        print(d.render(), file=sys.stderr)
    n = len(e.diagnostics)
    print(f"{n} error{'s' if n != 1 else ''}; nothing was run", file=sys.stderr)
    return EXIT_STATIC


def _fail(message: str, code: int) -> int:
    print(message, file=sys.stderr)
    return code


def _flush() -> None:
    try:
        sys.stdout.flush()
    except (BrokenPipeError, ValueError):
        # Output went to a closed pipe (rcl run x.rcl | head): stop quietly.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())


def entry() -> None:
    """Console-script entry point."""
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    sys.exit(main())
