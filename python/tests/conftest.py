"""Shared fixtures: paths into the repository and the optional C++ command line."""

import os
import pathlib

import pytest

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
VECTORS_FILE = REPOSITORY / "tests" / "vectors" / "grid_interpolation.json"


def find_slicecap_cli() -> pathlib.Path:
    """The C++ `slicecap` command built by scripts/build (or $SLICECAP_CLI); skips without it."""
    path = pathlib.Path(os.environ.get("SLICECAP_CLI", REPOSITORY / "build" / "app" / "slicecap"))
    if not path.is_file():
        pytest.skip(f"{path} is absent (run scripts/build); this test crosses into the C++ code")
    return path


@pytest.fixture
def slicecap_cli() -> pathlib.Path:
    """The C++ `slicecap` command (find_slicecap_cli)."""
    return find_slicecap_cli()


@pytest.fixture(scope="module")
def slicecap_cli_for_module() -> pathlib.Path:
    """The same, for fixtures that run the C++ side once per test module."""
    return find_slicecap_cli()
