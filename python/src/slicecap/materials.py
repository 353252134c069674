"""Loading a captured material by its file's `slicecap:layout`: the one place that knows which
layouts exist, so the renderer and the Mitsuba plugin need not.

Today there is one layout, "bonn81" (an ABRDF: one table for the whole surface). The texture
(BTF) layout of issue 7 will add a branch here returning an object whose `evaluate` also takes
texture coordinates; until then every other layout gets the ABRDF reader's error.
"""

from slicecap.abrdf import Abrdf
from slicecap.abrdf_exr import read_abrdf_exr
from slicecap.paths import StrPath


def load_material(path: StrPath) -> Abrdf:
    """The material in a slicecap EXR file. Raises SlicecapFileError naming the file."""
    return read_abrdf_exr(path)
