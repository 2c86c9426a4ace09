"""The interactive prompt: `rcl` or `rcl repl`.

Each input is a command (`:help`, `:type`, `:load`, `:vars`, `:reset`), a bare
expression (its value is printed) or statements (run). Input continues on
the next line while a block or an expression is still open ("the parse
ended early"). Ctrl-C stops a running statement and the robot; Ctrl-D leaves.
"""
from __future__ import annotations

import contextlib
import os
import re
import signal
import sys
import threading
from collections.abc import Callable
from pathlib import Path
from typing import TextIO

import numpy as np

from .errors import RclCancelled, RclRuntimeError, RclStaticError, report
from .frame import Frame
from .keywords import keywords
from .parser import needs_more_input, parse_expression
from .runreport import RunWatcher
from .session import FileNotReadable, Session
from .values import Array, format_real, format_value

PROMPT = "rcl> "
CONTINUATION = "...  "
COMMANDS = {
    ":help": ":help [NAME]   what a built-in or routine does; the commands",
    ":type": ":type EXPR     the static type of an expression",
    ":load": ":load FILE     check and run a file in this session",
    ":vars": ":vars          the variables and their values",
    ":reset": ":reset         forget every variable and routine",
    ":page": ":page DIR       write DIR/index.html: this session's looks, picks and arm in 3D (needs rcl[page])",
    ":quit": ":quit          leave (as Ctrl-D does)",
}
KEPT_LOOKS = 50  # :page shows the pictures of the session's latest looks only (3 MB each in memory)
_WORD = re.compile(r"[A-Za-z][A-Za-z0-9_]*\^?$")
# what newcomers type to get help or to leave, taken so when no RCL name of theirs is spelt so
PLAIN_WORDS = {"help": ":help", "help()": ":help", "exit": ":quit", "exit()": ":quit", "quit": ":quit",
               "quit()": ":quit"}


def doc_comment(source: str, line: int) -> str:
    """The { ... } comment that opens a routine's body (the line after its header), if any."""
    from .errors import source_lines

    lines = list(source_lines(source))[line:]
    if not lines or not lines[0].lstrip().startswith("{"):
        return ""
    text = []
    for ln in lines:
        text.append(ln.strip())
        if "}" in ln:
            break
    return "\n".join(text).lstrip("{").rsplit("}", 1)[0].strip()


def reference(word: str) -> str:
    """What docs/language.md (shipped with the package) says of a keyword: the lines of its
    shortest example block that start with it, the paragraph on it (or the one after the block),
    under the section's title; else the first line that names it."""
    from .resources import docs_dir

    try:
        text = (docs_dir() / "language.md").read_text(encoding="utf-8")
    except OSError:
        return ""
    blocks, section = [], ""
    for block in re.split(r"\n\s*\n", text):
        if block.startswith("## "):
            section = block.splitlines()[0][3:]
        blocks.append((section, block))
    starts = re.compile(rf"^\s*{re.escape(word)}\b", re.MULTILINE)
    found = [i for i, (_, b) in enumerate(blocks) if b.startswith("    ") and starts.search(b)]
    if not found:
        named = re.compile(rf"`{re.escape(word)}\b")
        for title, block in blocks:
            for line in block.splitlines():
                if named.search(line):
                    return f"docs/language.md, {title}:\n{line.strip()}"
        return ""
    i = min(found, key=lambda k: len(blocks[k][1].splitlines()))
    title, block = blocks[i]
    lines = block.splitlines()
    shown = ["\n".join(ln for ln in lines if starts.match(ln)) if len(lines) > 3 else block]
    about = [b for t, b in blocks if t == title and b.startswith(f"`{word}")]
    if about:
        shown.append(about[0])
    elif i + 1 < len(blocks) and not blocks[i + 1][1].startswith(("    ", "#")):
        shown.append(blocks[i + 1][1])
    return f"docs/language.md, {title}:\n" + "\n\n".join(shown)


def banner() -> str:
    from . import __version__

    return f"RCL {__version__}: type statements or an expression; :help for help; Ctrl-D or quit to leave"


class Repl:
    """The read-eval-print logic, separate from the terminal so that tests can drive it."""

    def __init__(self, new_session: Callable[[], Session], out: TextIO | None = None,
                 err: TextIO | None = None) -> None:
        self.new_session = new_session
        self.session = new_session()
        self.watcher = RunWatcher(self.session, keep_last=KEPT_LOOKS)  # what :page shows
        self._out = out
        self.err = err  # where errors go; None: with the rest (the terminal)
        self.status = 0  # the worst error so far: 2 static, 1 at run time, 130 Ctrl-C
        self.typeahead = ""  # keys typed while a statement ran, for the next prompt

    @property
    def out(self) -> TextIO:
        return self._out if self._out is not None else sys.stdout

    def say(self, text: str) -> None:
        self.out.write(text + "\n")
        self.out.flush()

    # One input ------------------------------------------------------------------

    def handle(self, text: str) -> bool:
        """Act on one complete input; False when the user asked to leave."""
        stripped = text.strip()
        if not stripped:
            return True
        word = PLAIN_WORDS.get(stripped.lower())
        if word is not None and stripped.rstrip("()").lower() not in self._user_names():
            return self.command(word)
        if stripped.startswith(":"):
            return self.command(stripped)
        try:
            try:
                parse_expression(stripped, "<stdin>")
            except RclStaticError:
                self.interruptible(lambda: self.session.run(text, "<stdin>", forget_on_error=True))
                return True
            value, rcl_type = self.interruptible(lambda: self.session.evaluate(stripped, "<stdin>"))
            if rcl_type is not None:
                self.say(show(value))
        except (RclStaticError, RclRuntimeError, RclCancelled, FileNotReadable) as e:
            text, code = report(e)
            self.failed(code, text)
        return True

    def failed(self, status: int, message: str) -> None:
        """Show an input's error (on the error stream, where one is given) and remember the worst."""
        self.status = max(self.status, status)
        if self.err is not None:
            self.err.write(message + "\n")
            self.err.flush()
        else:
            self.say(message)

    def replay(self, text: str) -> int:
        """Piped input, taken as if typed at the prompt: each complete input in turn (a block or an
        expression still open goes on to the next line). The exit status: 0, or the worst error's
        (2 static, 1 at run time, 130 Ctrl-C)."""
        pending = ""
        for line in text.splitlines(keepends=True):
            pending += line
            if pending.strip().startswith(":") or not needs_more_input(pending):
                go_on = self.handle(pending)
                pending = ""
                if not go_on:
                    return self.status
        if pending.strip():
            self.handle(pending)  # cut short: its error says what is missing
        return self.status

    def interruptible(self, action):
        """Run action in a worker thread; Ctrl-C meanwhile cancels the session's program.

        On a terminal the main thread reads the keyboard itself (the terminal without
        ISIG, so Ctrl-C is a byte, not a signal): a SIGINT taken by another thread is
        not always seen by a busy Python 3.11 process. Elsewhere SIGINT sets a flag.
        """
        result: dict = {}
        done = threading.Event()

        def work():
            try:
                result["value"] = action()
            except BaseException as e:  # handed to the main thread below
                result["error"] = e
            finally:
                done.set()
        stop = threading.Event()
        on_main = threading.current_thread() is threading.main_thread()
        # meanwhile SIGINT only raises a flag: no KeyboardInterrupt can land mid-way (say, in Thread.start)
        previous = signal.signal(signal.SIGINT, lambda *_: stop.set()) if on_main else None
        try:
            with _keyboard() as keys:
                threading.Thread(target=work, name="rcl statement", daemon=True).start()
                while not done.is_set():
                    if stop.is_set():  # again until the program has seen it (it may not have started)
                        self.session.cancel("interrupted (Ctrl-C)", by_user=True)
                    if keys is None:
                        done.wait(0.05)
                        continue
                    typed = keys(0.05)
                    if b"\x03" in typed:
                        stop.set()
                        typed = typed.split(b"\x03")[-1]
                    self.typeahead += _printable(typed)
        finally:
            if on_main:
                signal.signal(signal.SIGINT, previous)
        if "error" in result:
            raise result["error"]
        return result["value"]

    def command(self, text: str) -> bool:
        name, _, arg = text.partition(" ")
        arg = arg.strip()
        name = name.lower()
        if name in (":quit", ":q", ":exit"):
            return False
        if name == ":help":
            self.say(self.help(arg))
        elif name == ":type":
            try:
                t = self.session.type_of(arg)
                self.say(t if t is not None else "no value: a procedure call")
            except RclStaticError as e:
                self.say(report(e)[0])
        elif name == ":load":
            if not arg:
                self.say("usage: :load FILE")
            else:
                try:
                    self.interruptible(lambda: self.session.run_file(arg))
                except (RclStaticError, RclRuntimeError, RclCancelled, FileNotReadable) as e:
                    self.say(report(e)[0])
        elif name == ":vars":
            for line in self.variables():
                self.say(line)
        elif name == ":page":
            self.say(self.page(arg) if arg else "usage: :page DIR")
        elif name == ":reset":
            self.session = self.new_session()
            self.watcher = RunWatcher(self.session, keep_last=KEPT_LOOKS)
            self.say("a new session: every variable and routine is forgotten")
        else:
            self.say(f"unknown command {name}; :help lists them")
        return True

    def page(self, folder: str) -> str:
        """Write the page of this session so far into folder; what came of it."""
        from .runpage import PageError, write_page

        try:
            index = write_page(folder, self.watcher, {"program": "the REPL session"})
        except PageError as e:
            return f"error: {e}"
        except OSError as e:
            return f"error: cannot write into {folder}: {e.strerror or e}"
        return f"wrote {index}"

    def help(self, name: str) -> str:
        if not name:
            listing = ", ".join(sorted(self.session.builtins()))
            return "\n".join(["Type RCL statements or an expression; Ctrl-D leaves.", *COMMANDS.values(),
                              f"built-ins: {listing}"])
        key = name.lower()
        builtins = {b.name.lower(): b for b in self.session.builtins().values()}
        if key in builtins:
            b = builtins[key]
            return f"{b.signature()}\n{b.doc}" if b.doc else b.signature()
        routine = self.session.routines().get(key)
        if routine is not None:
            params = "; ".join(("VAR " if p.by_ref else "") + f"{p.name} : {p.type}" for p in routine.params)
            kind = "FUNCTION" if routine.is_function else "PROCEDURE"
            result = f" : {routine.result}" if routine.is_function else ""
            head = f"{kind} {routine.name}({params}){result}  (defined in {routine.module.filename})"
            doc = doc_comment(routine.module.source, routine.decl.span.line)
            return f"{head}\n{doc}" if doc else head
        if name.upper() in keywords():
            return reference(name.upper()) or f"{name.upper()} is a keyword; see docs/language.md"
        return f"no help for {name}"

    def _user_names(self) -> set[str]:
        """The variables and routines of this session, lower case."""
        names = {n.lower() for n in self.session.variables()}
        return names | set(self.session.routines())

    def variables(self) -> list[str]:
        lines = []
        for name, t in sorted(self.session.variables().items(), key=lambda kv: kv[0].lower()):
            value = self.session.get(name)
            shown = "(no value yet)" if value is None else show(value, short=True)
            lines.append(f"{name} : {t} = {shown}")
        return lines or ["no variables yet"]

    def completions(self, word: str) -> list[str]:
        """Keywords, built-ins, routines and variables starting with word (any case)."""
        key = word.lower()
        names = set(keywords()) | set(self.session.builtins())
        names |= {r.name for r in self.session.routines().values()}
        names |= set(self.session.variables())
        return sorted((n for n in names if n.lower().startswith(key)), key=str.lower)

    # The terminal loop ---------------------------------------------------------------

    def loop(self, input=None, output=None) -> int:
        from prompt_toolkit import PromptSession
        from prompt_toolkit.completion import Completer, Completion
        from prompt_toolkit.history import FileHistory, InMemoryHistory
        from prompt_toolkit.key_binding import KeyBindings
        from prompt_toolkit.lexers import PygmentsLexer

        from .highlight import RclLexer

        repl = self

        class RclCompleter(Completer):
            def get_completions(self, document, complete_event):
                m = _WORD.search(document.text_before_cursor)
                if m:
                    for name in repl.completions(m.group()):
                        yield Completion(name, start_position=-len(m.group()))

        keys = KeyBindings()

        @keys.add("enter")
        def _(event):
            buffer = event.current_buffer
            text = buffer.text
            if text.strip().startswith(":") or not needs_more_input(text):
                buffer.validate_and_handle()
            else:
                buffer.insert_text("\n")

        path = history_path()
        history = FileHistory(str(path)) if path is not None else InMemoryHistory()
        prompt: PromptSession = PromptSession(multiline=True, key_bindings=keys, lexer=PygmentsLexer(RclLexer),
                               completer=RclCompleter(), history=history, input=input, output=output,
                               prompt_continuation=lambda width, line, soft: CONTINUATION)
        self.say(banner())
        while True:
            ahead, self.typeahead = self.typeahead, ""
            if "\n" in ahead:  # a whole line typed while the last statement ran: run it now
                text, rest = ahead.split("\n", 1)
                self.typeahead = rest
                self.say(PROMPT + text)
                if text.strip():
                    history.append_string(text)
            else:
                try:
                    text = prompt.prompt(PROMPT, default=ahead)
                except KeyboardInterrupt:
                    continue  # Ctrl-C at the prompt drops the line
                except EOFError:
                    return 0
            if not self.handle(text):
                return 0


@contextlib.contextmanager
def _keyboard():
    """On a terminal: a function reading the keys typed within a timeout (Ctrl-C arrives as
    the byte 0x03); None elsewhere. The terminal's settings are restored afterwards."""
    try:
        import select
        import termios

        fd = sys.stdin.fileno()
        if not os.isatty(fd):
            raise OSError
        old = termios.tcgetattr(fd)
    except (OSError, ValueError, ImportError, AttributeError):
        yield None
        return
    new = termios.tcgetattr(fd)
    new[3] &= ~(termios.ICANON | termios.ECHO | termios.ISIG)
    new[6][termios.VMIN], new[6][termios.VTIME] = 0, 0
    termios.tcsetattr(fd, termios.TCSANOW, new)

    def read(timeout: float) -> bytes:
        ready, _, _ = select.select([fd], [], [], timeout)
        return os.read(fd, 64) if ready else b""
    try:
        yield read
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, old)


def _printable(data: bytes) -> str:
    """Typed bytes as text for the next prompt: Enter as a newline, control keys dropped."""
    text = data.decode("utf-8", "ignore").replace("\r", "\n")
    return "".join(c for c in text if c == "\n" or c == "\t" or c >= " ")


def show(value, short: bool = False) -> str:
    """A value for the REPL: a frame as its matrix with position and RPY angles."""
    if isinstance(value, Frame):
        roll, pitch, yaw = value.rpy_angles()
        x, y, z = (format_real(float(c)) for c in value.p)
        summary = (f"position ({x}, {y}, {z}) mm, RPY ({format_real(roll)}, {format_real(pitch)}, "
                   f"{format_real(yaw)}) degrees")
        if short:
            return summary
        rows = "\n".join("  [" + "  ".join(f"{c:10.4f}" for c in row) + " ]" for row in value.matrix)
        return f"{rows}\n  {summary}"
    if isinstance(value, list):
        return format_value(Array(0, list(value)))
    if isinstance(value, np.ndarray):
        return format_value(value)
    return format_value(value)


def history_path() -> Path | None:
    """Where the history is kept: $RCL_HISTORY, else the XDG state folder; None if not writable."""
    if os.environ.get("RCL_HISTORY"):
        path = Path(os.environ["RCL_HISTORY"])
    else:
        base = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
        path = Path(base) / "rcl" / "history"
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.touch(exist_ok=True)
    except OSError:
        return None
    return path

