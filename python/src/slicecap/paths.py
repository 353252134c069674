"""Path checks shared by the command-line entry points."""

import os
from collections.abc import Callable

# A path as the standard library takes it: a str or an os.PathLike (pathlib.Path).
StrPath = str | os.PathLike[str]


def same_file(a: StrPath, b: StrPath) -> bool:
    """True when both paths name one existing file (the same path, a symbolic or a hard link):
    a command's output that is one of its inputs would overwrite it."""
    try:
        return os.path.samefile(a, b)
    except (OSError, TypeError, ValueError):
        return False


def write_replacing(path: StrPath, write: Callable[[str], object]) -> None:
    """Calls write(temporary) on PATH.tmp beside PATH, then renames it onto PATH, as the C++
    writers do: a write that fails (a full disk) or is interrupted leaves the previous PATH as it
    was, never a truncated file that looks whole. A device such as /dev/null is written directly.
    Raises whatever write raises, or OSError when the rename fails; the temporary is removed."""
    target = os.fspath(path)
    if os.path.exists(target) and not os.path.isfile(target) and not os.path.isdir(target):
        write(target)
        return
    temporary = target + ".tmp"
    try:
        write(temporary)
        os.replace(temporary, target)
    except BaseException:
        try:
            os.remove(temporary)
        except OSError:
            pass
        raise
