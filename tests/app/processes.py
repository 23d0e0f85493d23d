"""Helpers for the app tests that watch the solver processes."""

from __future__ import annotations

import os


def alive(pid: int) -> bool:
    """Whether process ``pid`` runs (a zombie does not; a finished child is reaped by the
    thread that waits for it). It can end between any two of these steps: reading its
    /proc entry then fails as the signal does."""
    try:
        os.kill(pid, 0)
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(") ")[-1][0] != "Z"
    except (ProcessLookupError, FileNotFoundError):
        return False
