"""The console scripts pyproject.toml declares: installed beside the interpreter (the venv's bin),
each answers --help with its own name in the usage line."""

import pathlib
import subprocess
import sys
import sysconfig

import pytest

SCRIPTS = ("slicecap-render", "slicecap-export-merl", "slicecap-viewer")


@pytest.mark.parametrize("name", SCRIPTS)
def test_an_installed_console_script_answers_help(name):
    script = pathlib.Path(sysconfig.get_path("scripts")) / name
    if not script.exists():
        pytest.skip(f"{script} is not installed (pip install ./python makes it)")
    run = subprocess.run([script, "--help"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith(f"usage: {name} "), run.stdout


@pytest.mark.parametrize("module", ("render", "export_merl", "viewer"))
def test_python_dash_m_names_itself_in_the_usage(module):
    run = subprocess.run([sys.executable, "-m", f"slicecap.{module}", "--help"],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith(f"usage: python -m slicecap.{module} "), run.stdout
