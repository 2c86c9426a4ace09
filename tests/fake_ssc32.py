"""A fake SSC-32 on a pseudo-terminal, for tests: never hardware."""
from __future__ import annotations

import os
import re
import threading


class FakeSSC32:
    """Answers VER, Q ('+' once after each move, then '.'), QP<ch> (pulse / 10) like an SSC-32
    and records every byte it receives. mode: "ok", "garbage" (answers Q with junk) or
    "silent" (stops answering after VER and the QPs)."""

    def __init__(self, mode: str = "ok", pulses=None) -> None:
        self.master, self.slave = os.openpty()
        self.path = os.ttyname(self.slave)
        self.mode = mode
        self.received = bytearray()
        self.pulses = dict(pulses or {})
        self.moving = False
        self._buffer = b""
        self._stop = False
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        while not self._stop:
            try:
                data = os.read(self.master, 1024)
            except OSError:
                return
            self.received += data
            self._buffer += data
            while b"\r" in self._buffer:
                line, self._buffer = self._buffer.split(b"\r", 1)
                reply = self._answer(line.lstrip(b"\x1b").decode("ascii", "replace"))
                if reply:
                    os.write(self.master, reply)

    def _answer(self, cmd: str) -> bytes:
        if cmd == "VER":
            return b"SSC32-V2.50USB\r"
        if cmd.startswith("QP"):
            if self.mode == "silent" and self.received.count(b"#"):
                return b""
            return bytes([self.pulses.get(int(cmd[2:]), 0) // 10])
        if cmd == "Q":
            if self.mode == "silent":
                return b""
            if self.mode == "garbage":
                return b"x"
            if self.moving:
                self.moving = False
                return b"+"
            return b"."
        if cmd.startswith("#"):
            for ch, pw in re.findall(r"#(\d+)P(\d+)", cmd):
                self.pulses[int(ch)] = int(pw)
            self.moving = True
        return b""

    def close(self) -> None:
        self._stop = True
        for fd in (self.slave, self.master):
            try:
                os.close(fd)
            except OSError:
                pass
