"""A progress bar on stderr for multi-object work (stdlib only)."""
from __future__ import annotations

import sys
from typing import Optional, TextIO


class Progress:
    """``[#####-----] 3/6 label`` redrawn in place on a terminal; one line per step
    otherwise (logs, CI). ``enabled=False`` prints nothing."""

    def __init__(self, total: int, stream: Optional[TextIO] = None, width: int = 24, enabled: bool = True):
        self.total, self.done, self.width = max(int(total), 1), 0, width
        self.stream = sys.stderr if stream is None else stream
        self.enabled = enabled
        self.tty = enabled and hasattr(self.stream, "isatty") and self.stream.isatty()

    def step(self, label: str) -> None:
        """Count one unit of work done and show ``label``."""
        self.done = min(self.done + 1, self.total)
        if not self.enabled:
            return
        filled = self.width * self.done // self.total
        bar = f"[{'#' * filled}{'-' * (self.width - filled)}] {self.done}/{self.total} {label}"
        if self.tty:
            end = "\n" if self.done == self.total else ""
            self.stream.write("\r\x1b[2K" + bar + end)
        else:
            self.stream.write(bar + "\n")
        self.stream.flush()
