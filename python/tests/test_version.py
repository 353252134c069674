"""One version: slicecap.__version__ (slicecap/_version.py, which pyproject.toml reads) is the
project version of the top-level CMakeLists.txt, and the installed package's metadata says it."""

import importlib.metadata
import pathlib
import re

import pytest

import slicecap

CMAKE_LISTS = pathlib.Path(__file__).resolve().parents[2] / "CMakeLists.txt"


def cmake_project_version(text: str) -> str:
    match = re.search(r"\bproject\(\s*slicecap\s+VERSION\s+([0-9][0-9.]*)", text)
    if match is None:
        raise AssertionError(f"{CMAKE_LISTS}: no project(slicecap VERSION x.y.z ...)")
    return match.group(1)


def test_the_package_version_is_the_cmake_project_version():
    if not CMAKE_LISTS.is_file():
        pytest.skip(f"{CMAKE_LISTS} is not there (tests run outside a source tree)")
    assert slicecap.__version__ == cmake_project_version(CMAKE_LISTS.read_text(encoding="utf-8"))


def test_the_installed_metadata_has_the_package_version():
    try:
        installed = importlib.metadata.version("slicecap")
    except importlib.metadata.PackageNotFoundError:
        pytest.skip("slicecap is not installed (imported from its source folder)")
    assert installed == slicecap.__version__


def test_files_written_by_python_carry_the_package_version():
    from slicecap.abrdf_exr import VERSION

    assert VERSION == f"{slicecap.__version__} (python)"
