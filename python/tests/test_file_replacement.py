"""Every writer of the package replaces its file whole or not at all (paths.write_replacing): a
write that fails part-way, here a file-size limit as a full disk would, leaves the previous file
as it was and no temporary behind."""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

from slicecap import read_abrdf_exr, write_abrdf_exr
from slicecap.merl import export_merl, read_merl
from slicecap.png import write_png

# The writer's call in a child process with a 4 KiB file-size limit (SIGXFSZ ignored, so the
# write fails with EFBIG instead of killing the process); prints the exception's type.
CHILD = textwrap.dedent(
    """
    import resource, signal, sys
    import numpy as np
    from slicecap import write_abrdf_exr
    from slicecap.merl import export_merl
    from slicecap.png import write_png
    kind, path = sys.argv[1], sys.argv[2]
    rng = np.random.default_rng(7)
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (4096, resource.RLIM_INFINITY))
    try:
        if kind == "exr":
            write_abrdf_exr(path, rng.random((81, 81, 3), dtype=np.float32))
        elif kind == "png":
            write_png(path, rng.integers(0, 256, (96, 96, 3), dtype=np.uint8))
        else:
            export_merl(path, np.full((81, 81, 3), 0.5, np.float32))
    except Exception as e:
        print(type(e).__name__, e)
        sys.exit(1)
    """
)


def previous_file(kind, path):
    if kind == "exr":
        write_abrdf_exr(path, np.full((81, 81, 3), 0.25, np.float32))
    elif kind == "png":
        write_png(path, np.full((8, 8, 3), 200, np.uint8))
    else:
        export_merl(path, np.full((81, 81, 3), 0.125, np.float32))
    return path.read_bytes()


@pytest.mark.parametrize("kind", ["exr", "png", "merl"])
def test_a_failed_write_leaves_the_previous_file_whole(tmp_path, kind):
    path = tmp_path / f"out.{kind}"
    before = previous_file(kind, path)
    child = subprocess.run(
        [sys.executable, "-c", CHILD, kind, str(path)], capture_output=True, text=True
    )
    assert child.returncode == 1, child.stdout + child.stderr
    assert str(path) in child.stdout, child.stdout  # the error names the file
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]
    if kind == "exr":
        assert float(read_abrdf_exr(path).values.max()) == 0.25
    elif kind == "merl":
        assert read_merl(path).shape[0] == 3


def test_a_write_replaces_the_file_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "t.exr"
    write_abrdf_exr(path, np.full((81, 81, 3), 0.25, np.float32))
    write_abrdf_exr(path, np.full((81, 81, 3), 0.5, np.float32))
    assert float(read_abrdf_exr(path).values.min()) == 0.5
    assert [p.name for p in tmp_path.iterdir()] == ["t.exr"]
