"""The peak resident memory of this process since a point: writing ``5`` to
``/proc/self/clear_refs`` resets the kernel's high-water mark (``VmHWM`` in
``/proc/self/status``) to the memory resident now, so that a long-lived worker measures each
input on its own."""

from __future__ import annotations


def reset_peak() -> bool:
    """Reset the high-water mark; False where the kernel does not allow it (no ``/proc``)."""
    try:
        with open("/proc/self/clear_refs", "w", encoding="ascii") as stream:
            stream.write("5")
        return True
    except OSError:
        return False


def peak_kb() -> int:
    """``VmHWM`` in KiB (0 when it cannot be read)."""
    try:
        with open("/proc/self/status", encoding="ascii", errors="replace") as stream:
            for line in stream:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return 0
