"""The `rcl` command: run and check RCL programs, calibrate, and the interactive prompt.

    rcl [repl]          the interactive prompt (piped input runs as a script)
    rcl run FILE        exit 0 ok, 1 runtime error, 2 static errors, 130 interrupted
    rcl check FILE...   exit 0 clean, 2 static errors
    rcl calib fit|apply camera models

Only this module and the REPL print diagnostics.
"""
from __future__ import annotations

import argparse
import contextlib
import math
import os
import signal
import sys
from collections.abc import Sequence
from pathlib import Path

from . import __version__
from .errors import (
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_RUNTIME,
    EXIT_STATIC,
    RclCancelled,
    RclRuntimeError,
    RclStaticError,
    report,
)

CTRL_C_GRACE_S = 0.5  # after Ctrl-C, how long a program has to reach a statement where it can stop


def main(argv: Sequence[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.command is None:
        args = parser.parse_args(["repl", *(argv if argv is not None else sys.argv[1:])])
    try:
        return args.handler(args)
    except KeyboardInterrupt:  # Ctrl-C outside a running program (reading, checking, vision): nothing moved
        _flush()
        return _fail("rcl: interrupted (Ctrl-C)", EXIT_INTERRUPTED)


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="rcl", description="RCL, the Robot Control Language.")
    p.add_argument("--version", action="version", version=f"rcl {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    setup = argparse.ArgumentParser(add_help=False)
    setup.add_argument("--step-budget", type=_positive_int, metavar="N",
                       help="stop after N loop iterations and routine calls")
    setup.add_argument("--time-limit", type=_positive_seconds, metavar="SECONDS",
                       help="stop a program after this many seconds (the robot is halted; exit 1)")
    setup.add_argument("--camera", metavar="PATH",
                       help="the camera: an image file (the same picture every look) or a folder of images")
    setup.add_argument("--robot", default="sim", metavar="sim|ssc32:PORT[@BAUD]",
                       help="the arm: the simulator (default) or an SSC-32 controller on a serial port")
    setup.add_argument("--model", metavar="NAME|FILE.toml",
                       help="the arm model: smartarms (default for sim), al5d (default for ssc32), puma560, "
                            "or a model file")
    setup.add_argument("--realtime", action="store_true", help="the simulator takes real time for its motions")
    setup.add_argument("--plot", metavar="FILE.png", help="the simulator draws the path of T5 into FILE.png")
    setup.add_argument("--cell", metavar="FILE.toml",
                       help="the work cell's description (default: the built-in simulated cell); "
                            "--camera, --robot and --model replace its parts")
    setup.add_argument("--seed", type=_natural, default=0, metavar="N",
                       help="the simulated cell's tray of wires (default 0)")
    setup.add_argument("--data", action="append", default=[], metavar="DIR",
                       help="a folder the program may read and write files in (LOADWARP, SAVEWARP) besides "
                            "its own and the cell file's; the first is where relative names start")
    run = sub.add_parser("run", parents=[setup], help="check and run an .rcl program")
    run.add_argument("file", metavar="FILE")
    run.add_argument("--report", metavar="FILE.json",
                     help="write how the run went on the simulated cell: wires, attempts, failures, timings")
    run.add_argument("--pictures", metavar="DIR",
                     help="write a PNG per look: the camera image, what vision saw, the grasp and the outcome")
    run.add_argument("--frames", metavar="DIR",
                     help="write each look's raw camera image, frame-NNN.png (numbered as the pictures), "
                          "to try `rcl vision` on")
    run.add_argument("--page", metavar="DIR",
                     help="write DIR/index.html, a page of the run that opens offline: summary, timeline, "
                          "each look's pictures and a 3D view of the cell and the arm (needs rcl[page])")
    run.set_defaults(handler=_run)
    repl = sub.add_parser("repl", parents=[setup], help="the interactive prompt (the default command)")
    repl.set_defaults(handler=_repl, file="<stdin>")
    check = sub.add_parser("check", help="check .rcl programs without running them")
    check.add_argument("files", nargs="+", metavar="FILE")
    check.add_argument("--cell", metavar="FILE.toml", help="the work cell whose frames IMPORT 'cell' gives")
    check.set_defaults(handler=_check)
    vision = sub.add_parser("vision", help="find graspable wire ends in images")
    vision.add_argument("images", nargs="+", metavar="IMAGE")
    vision.add_argument("--method", choices=("ridge", "grey", "binary"), default="ridge",
                        help="ridge: the default finder (centre lines as ridges, colour-aware); grey or binary: "
                             "the paper's grey-scale or binary system")
    vision.add_argument("--px-per-mm", type=float, default=4.0, metavar="SCALE",
                        help="the images' scale (default 4)")
    vision.add_argument("--json", action="store_true", help="one JSON object per image and line")
    vision.add_argument("--overlay", metavar="DIR",
                        help="write a PNG per image: what was seen, every candidate, the chosen end and grasp")
    vision.set_defaults(handler=_vision)
    calib = sub.add_parser("calib", help="fit and apply camera models")
    calib_sub = calib.add_subparsers(dest="calib_command", metavar="ACTION", required=True)
    fit = calib_sub.add_parser("fit", help="fit a camera model to a CSV of points")
    fit.add_argument("points", metavar="POINTS.csv", help="header u,v,x,y (warp) or u,v,x,y,z (linear)")
    fit.add_argument("--model", choices=("warp", "linear"), default="warp")
    fit.add_argument("--z", type=float, default=0.0, help="the tray plane of a warp, mm (default 0)")
    fit.add_argument("-o", "--output", metavar="MODEL.json", required=True)
    fit.set_defaults(handler=_calib_fit)
    apply = calib_sub.add_parser("apply", help="map image points to the tray with a camera model")
    apply.add_argument("model", metavar="MODEL.json")
    apply.add_argument("query", metavar="QUERY.csv", help="header u,v (warp) or u,v,z (linear)")
    apply.set_defaults(handler=_calib_apply)
    return p


def _natural(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if n < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more: {n}")
    return n


def _positive_seconds(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (math.isfinite(x) and x > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds: {text}")
    return x


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if n <= 0:
        raise argparse.ArgumentTypeError(f"must be positive: {n}")
    return n


def _robot(args):
    """The robot the options ask for; RobotError says what is wrong."""
    from .robots import RobotError, SimRobot

    spec = args.robot
    if spec == "sim":
        return SimRobot(args.model or "smartarms", realtime=args.realtime)
    if spec.startswith("ssc32:") and len(spec) > 6:
        from .robots.serial_arm import SerialRobot

        port, _, baud = spec[6:].partition("@")
        if baud and not baud.isdigit():
            raise RobotError(f"the baud rate must be a whole number, not {baud!r}")
        return SerialRobot(port, args.model or "al5d", int(baud) if baud else None)
    raise RobotError(f"unknown robot {spec!r}: use sim or ssc32:PORT[@BAUD]")


class _SetupError(Exception):
    """An option that names a camera or robot that cannot be had."""


def _config(args, arm=None):
    from .cell import CellConfigError, load_config

    try:
        return load_config(args.cell, arm=None if args.cell else arm)
    except CellConfigError as e:
        raise _SetupError(f"rcl: error: --cell: {e}") from None


def _open_cell(args):
    """The cell the options ask for: the described one, or its frames with the parts named by hand."""
    from .camera import ImageError, ImageFiles
    from .robots import RobotError
    from .workcell import Cell, CellSetupError, open_cell

    option = "--cell"
    sim_arm = args.model if args.model and not args.camera and args.robot == "sim" else None
    config = _config(args, arm=sim_arm)  # without --cell: the built-in cell laid out for that arm, if one ships
    if sim_arm and config.simulated:  # the simulated cell with that arm
        if args.cell:
            config.data["robot"]["model"] = sim_arm
        args.model, option = None, "--model"
    if args.camera or args.robot != "sim" or args.model:
        try:
            camera = ImageFiles(args.camera) if args.camera else None
        except ImageError as e:
            raise _SetupError(f"rcl: error: --camera: {e}") from None
        try:
            robot = _robot(args)
        except RobotError as e:
            raise _SetupError(f"rcl: error: --robot: {e}") from None
        return Cell(config, robot, camera, None)
    try:
        return open_cell(config, seed=args.seed, realtime=args.realtime)
    except CellSetupError as e:
        raise _SetupError(f"rcl: error: {option}: {e}") from None


def _finish(robot, args) -> None:
    if args.plot and hasattr(robot, "save_plot"):
        robot.save_plot(args.plot)
    if hasattr(robot, "close_port"):
        robot.close_port()


def _with_setup(args, body) -> int:
    """body(cell, new_session) with the cell the options ask for; its robot is finished after."""
    from .session import Session

    for folder in args.data:
        if not Path(folder).is_dir():
            return _fail(f"rcl: error: --data: {folder} is not a folder", EXIT_STATIC)
    try:
        cell = _open_cell(args)
    except _SetupError as e:
        return _fail(str(e), EXIT_STATIC)
    try:
        return body(cell, lambda: Session(step_budget=args.step_budget, cell=cell, data=args.data,
                                          time_limit=args.time_limit))
    finally:
        _finish(cell.robot, args)


def _run(args) -> int:
    if args.page:  # said before the run, not after it
        from .runpage import PageError, plotly_script

        try:
            plotly_script()
        except PageError as e:
            return _fail(f"rcl: error: --page: {e}", EXIT_STATIC)
    if hasattr(sys.stdout, "reconfigure"):
        sys.stdout.reconfigure(line_buffering=True)  # a long task's lines show as they come, piped too

    def body(cell, new_session) -> int:
        from .runreport import RunWatcher

        session = new_session()
        watcher = RunWatcher(session) if cell.sim is not None or args.page else None
        said: list[str] = []
        code = _run_session(session, args, said=said)
        if watcher is not None and code != EXIT_STATIC:
            meta = {"program": args.file, "cell": cell.config.name,
                    "seed": args.seed if cell.sim is not None else None, "error": "\n".join(said) or None}
            line, problems = watcher.finish(args.report, args.pictures, args.frames, args.page, meta)
            if line:
                print(line, flush=True)
            for problem in problems:
                print(problem, file=sys.stderr)
            code = (EXIT_RUNTIME if problems else EXIT_OK) or code
        return code
    return _with_setup(args, body)


def _repl(args) -> int:
    def body(cell, new_session) -> int:
        from .repl import Repl

        if not sys.stdin.isatty():  # piped input: each line as if typed at the prompt
            try:
                return Repl(new_session, err=sys.stderr).replay(sys.stdin.read())
            finally:
                _flush()
        return Repl(new_session).loop()
    return _with_setup(args, body)


@contextlib.contextmanager
def _ctrl_c_stops_at_a_statement(session):
    """The first Ctrl-C asks the program to stop at its next loop iteration or call, where the
    message can say FILE:LINE:COL and the call stack; if it has not stopped within
    CTRL_C_GRACE_S (a long motion, a look), Python's KeyboardInterrupt follows, as does a second
    Ctrl-C at once. Where SIGINT is ignored (a background job), it stays ignored."""
    import _thread
    import threading

    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    timers = []

    def first(signum, frame):
        session.cancel("interrupted (Ctrl-C)", by_user=True)
        signal.signal(signal.SIGINT, signal.default_int_handler)
        timers.append(threading.Timer(CTRL_C_GRACE_S, _thread.interrupt_main))
        timers[-1].daemon = True
        timers[-1].start()

    signal.signal(signal.SIGINT, first)
    try:
        yield
    finally:
        for t in timers:
            t.cancel()
        signal.signal(signal.SIGINT, signal.default_int_handler)


def _run_session(session, args, source: str | None = None, said: list[str] | None = None) -> int:
    """Run the program; its exit status. said: where the error message, if any, is also put."""
    from .session import FileNotReadable, RclInternalError

    def failed(message: str, code: int) -> int:
        if said is not None:
            said.append(message)
        return _fail(message, code)

    try:
        with _ctrl_c_stops_at_a_statement(session):
            if source is None:
                session.run_file(args.file)
            else:
                session.run(source, args.file)
    except FileNotReadable as e:
        return failed(f"rcl: error: {e}", EXIT_STATIC)
    except RclStaticError as e:
        return _report_static(e)
    except (RclRuntimeError, RclCancelled) as e:
        return failed(*report(e))
    except RclInternalError as e:
        if os.environ.get("RCL_DEBUG"):
            raise
        return failed(f"rcl: {e} (a fault in RCL itself; set RCL_DEBUG=1 to see where)", EXIT_RUNTIME)
    finally:
        _flush()
    return EXIT_OK


def _check(args) -> int:
    from .session import FileNotReadable, Session
    from .workcell import Cell

    try:
        cell = Cell(_config(args), None, None, None)
    except _SetupError as e:
        return _fail(str(e), EXIT_STATIC)
    status = EXIT_OK
    for path in args.files:
        try:
            diagnostics = Session(cell=cell).check_file(path)
        except FileNotReadable as e:
            print(f"rcl: error: {e}", file=sys.stderr)
            status = EXIT_STATIC
            continue
        if diagnostics:
            _report_static(RclStaticError(diagnostics))
            status = EXIT_STATIC
        else:
            lines = Path(path).read_text(encoding="utf-8", errors="replace").count("\n")
            plural = "s" if lines != 1 else ""
            print(f"{path}: no errors ({lines} line{plural} and their imports: syntax, names, types, frame rules and "
                  f"references checked)")
    return status


def _vision(args) -> int:
    import json
    import time

    from .camera import ImageError, read_image
    from .vision import VisionError, find_wires, load

    load(args.method)  # the method's code and tables before any clock starts: time_ms is processing only
    status = EXIT_OK
    for path in args.images:
        try:
            image = read_image(path)
            t0 = time.perf_counter()
            result = find_wires(image, args.method, args.px_per_mm)
            elapsed = (time.perf_counter() - t0) * 1000.0
        except (ImageError, VisionError) as e:
            status = EXIT_STATIC
            if args.json:
                print(json.dumps({"image": path, "method": args.method, "error": str(e)}))
            else:
                print(f"rcl vision: error: {e}", file=sys.stderr)
            continue
        if args.overlay:
            problem = _write_overlay(args.overlay, path, image, result)
            if problem:
                print(f"rcl vision: error: {problem}", file=sys.stderr)
                status = EXIT_STATIC
        wires = [{"end": [round(s.end[0], 2), round(s.end[1], 2)], "end_angle": round(s.end_angle, 2),
                  "grasp": [round(s.grasp[0], 2), round(s.grasp[1], 2)], "grasp_angle": round(s.grasp_angle, 2),
                  "score": round(s.score, 3)} for s in result.candidates]
        if args.json:
            print(json.dumps({"image": path, "method": args.method, "wires": wires, "time_ms": round(elapsed, 3),
                              "stages_ms": {k: round(v, 3) for k, v in result.timings.items()}}))
        else:
            print(f"{path}: {len(wires)} graspable wire end{'s' if len(wires) != 1 else ''} "
                  f"({args.method}, {elapsed:.1f} ms)")
            for w in wires:
                print(f"  end {w['end']} into the wire at {w['end_angle']} deg; grasp {w['grasp']} "
                      f"along {w['grasp_angle']} deg")
    return status


def _write_overlay(folder: str, path: str, image, result) -> str:
    """Write the overlay PNG for one image; an error message, or "" when written."""
    from .vision.overlay import draw

    out = Path(folder)
    try:
        out.mkdir(parents=True, exist_ok=True)
        name = out / (Path(path).stem + ".png")
        draw(image, result).save(name)
    except OSError as e:
        return f"cannot write the overlay for {path} in {folder}: {e.strerror or e}"
    return ""


def _calib_fit(args) -> int:
    from .camera import BicubicWarp, CameraModelError, LinearCamera, fileformat
    from .camera.csvfile import read_columns

    model: BicubicWarp | LinearCamera
    try:
        if args.model == "warp":
            pts = read_columns(args.points, ("u", "v", "x", "y"))
            model, report = BicubicWarp.fit(pts[:, :2], pts[:, 2:4], args.z)
            z, what = args.z, "a bicubic warp (16 terms)"
        else:
            pts = read_columns(args.points, ("u", "v", "x", "y", "z"))
            model, report = LinearCamera.fit(pts[:, 2:5], pts[:, :2])
            z, what = args.z, "the linear 3x4 camera"
        fileformat.save(args.output, model, z, report)
    except CameraModelError as e:
        return _fail(f"rcl calib: error: {e}", EXIT_STATIC)
    print(f"fitted {what} to {report.points} points; wrote {args.output}")
    print("point,u,v,x,y,dx_mm,dy_mm,residual_mm")
    for i, (row, (dx, dy)) in enumerate(zip(pts, report.residuals), start=1):
        print(f"{i},{row[0]:.6g},{row[1]:.6g},{row[2]:.6g},{row[3]:.6g},{dx:.4g},{dy:.4g},{(dx * dx + dy * dy) ** 0.5:.4g}")
    print(f"max {report.max:.6g} mm")
    loo = "n/a (every point is needed)" if report.loo_rms is None else f"{report.loo_rms:.6g} mm"
    print(f"leave-one-out rms {loo}")
    print(f"rms {report.rms:.6g} mm")
    return EXIT_OK


def _calib_apply(args) -> int:
    from .camera import BicubicWarp, CameraModelError, fileformat
    from .camera.csvfile import read_columns

    try:
        model, z, _ = fileformat.load(args.model)
        if isinstance(model, BicubicWarp):
            q = read_columns(args.query, ("u", "v"))
            x, y = model(q[:, 0], q[:, 1])
        else:
            q = read_columns(args.query, ("u", "v", "z"))
            x, y = model.inverse_perspective(q[:, 0], q[:, 1], q[:, 2])
    except CameraModelError as e:
        return _fail(f"rcl calib: error: {e}", EXIT_STATIC)
    print("x,y")
    for a, b in zip(x, y):
        print(f"{a:.10g},{b:.10g}")
    return EXIT_OK


def _report_static(e: RclStaticError) -> int:
    print(report(e)[0], file=sys.stderr)
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
