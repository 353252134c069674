"""The package's version: the one place the Python side states it. pyproject.toml reads it from
here; tests/test_version.py holds it equal to the project version in the top-level CMakeLists.txt.
"""

__version__ = "0.1.0"
