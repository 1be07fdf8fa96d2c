"""Progress of a long ``check`` on stderr: ``checking 3/12 models/arm.uml``, rewritten in place.

Shown only when stderr is a terminal: at once when there are several files, after a moment
for a single one; the line is cleared when the run ends.
"""

from __future__ import annotations

import threading
from typing import TextIO

DELAY = 0.5  # seconds before a single file's progress appears


class Progress:
    def __init__(self, total: int, stream: TextIO) -> None:
        self.total = total
        self.stream = stream
        self.enabled = _is_terminal(stream)
        self.width = 0
        self.lock = threading.Lock()
        self.timer: threading.Timer | None = None

    def show(self, index: int, name: str) -> None:
        if not self.enabled:
            return
        text = f"checking {index}/{self.total} {name}"
        if self.total > 1:
            self._write(text)
        else:
            self.timer = threading.Timer(DELAY, self._write, (text,))
            self.timer.daemon = True
            self.timer.start()

    def _write(self, text: str) -> None:
        with self.lock:
            pad = " " * max(0, self.width - len(text))
            self.stream.write(f"\r{text}{pad}")
            self.stream.flush()
            self.width = len(text)

    def clear(self) -> None:
        if self.timer is not None:
            self.timer.cancel()
        with self.lock:
            if self.width:
                self.stream.write("\r" + " " * self.width + "\r")
                self.stream.flush()
                self.width = 0


def _is_terminal(stream: TextIO) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False
