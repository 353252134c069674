"""Path checks shared by the command-line entry points."""

import os


def same_file(a, b) -> bool:
    """True when both paths name one existing file (the same path, a symbolic or a hard link):
    a command's output that is one of its inputs would overwrite it."""
    try:
        return os.path.samefile(a, b)
    except (OSError, TypeError, ValueError):
        return False
