"""slicecap on the desktop: read, evaluate, render and export slicecap's ABRDF EXR files.

The box exports an apparent BRDF as an 81 x 81 table on the Bonn grid
(docs/reference/file-formats.md); this package reads it into numpy with the same checks as the C++
reader, evaluates it at any light and view directions exactly as the C++ `slicecap::evaluate` does,
exports isotropic tables to the MERL binary format, and (with mitsuba installed) renders it through
the Mitsuba 3 BSDF `slicecap`.
"""

from slicecap._version import __version__
from slicecap.abrdf import Abrdf
from slicecap.abrdf_exr import SlicecapFileError, read_abrdf_exr, write_abrdf_exr
from slicecap.btf import Btf, read_btf
from slicecap.grid import direction_of_index, tabulate
from slicecap.interpolation import evaluate
from slicecap.materials import load_material

__all__ = [
    "__version__",
    "Abrdf",
    "Btf",
    "SlicecapFileError",
    "direction_of_index",
    "evaluate",
    "load_material",
    "read_abrdf_exr",
    "read_btf",
    "tabulate",
    "write_abrdf_exr",
]
