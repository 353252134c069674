"""The viewer given a directory (slicecap-viewer DIR, docs/material-viewer.md): a `slicecap export`
folder shows the table its manifest lists first with the daemon's fit, a page for each SVBRDF maps
folder inside; a folder without a manifest shows its one table and that table's fit by name; bad
exports are refused naming the file; --serve serves the same bytes on 127.0.0.1 only."""

import base64
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import urllib.error
import urllib.request

import numpy as np
import pytest
from conftest import find_slicecap_cli
from svbrdf_maps_fixture import brushed_tiles, write_maps
from test_viewer import STEEL, VELVET, fit_document, page_data

import slicecap
from slicecap import viewer
from slicecap.abrdf_exr import SlicecapFileError, write_abrdf_exr
from slicecap.grid import tabulate
from slicecap.viewer_export import find_contents
from slicecap.viewer_serve import make_server

SESSION = "felt"
PANEL = "128"


def write_export(directory, session=SESSION):
    """An export folder as `slicecap export SESSION -o DIR` leaves it (lib/daemon
    session_exporter.cpp, lib/cli daemon_commands.cpp): tables SESSION-abrdf-METHOD.exr (the
    asked method, prior here, first in the manifest, though it sorts after b), previews, the fit
    of the first table and its exports, slices CSV, summary, texture copy, SESSION-manifest.json
    in the order the export made them."""
    directory.mkdir(parents=True, exist_ok=True)
    files = []

    def add(name, content):
        path = directory / name
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)
        files.append(name)

    for method, material in (("prior", VELVET), ("b", STEEL)):
        name = f"{session}-abrdf-{method}.exr"
        write_abrdf_exr(directory / name, tabulate(material.evaluate),
                        {"method": method, "session": session})
        files.append(name)
        add(f"{session}-abrdf-{method}.png", b"\x89PNG preview")
    add(f"{session}-material.json", json.dumps(fit_document(VELVET)))
    add(f"{session}-material.gltf", "{}")
    add(f"{session}-slices.csv", "slice,sample\n")
    add(f"{session}-summary.json", json.dumps({"id": session}))
    (directory / f"{session}-texture").mkdir()
    files.append(f"{session}-texture")
    (directory / f"{session}-manifest.json").write_text(
        json.dumps({"format": 1, "set": session, "files": files}))
    return directory


@pytest.fixture(scope="module")
def export(tmp_path_factory):
    """The export, with the maps of its texture (slicecap btf, slicecap fit) inside."""
    directory = write_export(tmp_path_factory.mktemp("export") / "felt")
    write_maps(directory / "felt-maps", brushed_tiles(4))
    output = directory.parent / "view.html"
    assert viewer.run([str(directory), "-o", str(output), "--panel-size", PANEL]) == 0
    return {"dir": directory, "page": output, "maps_page": directory.parent / "view-felt-maps.html"}


def table_of(page: str) -> np.ndarray:
    data = page_data(page)["table"]
    return np.frombuffer(base64.b64decode(data["values_base64"]), "<f4").reshape(81, 81, 3)


def test_export_shows_the_manifest_s_first_table_with_the_daemon_s_fit(export):
    data = page_data(export["page"].read_text(encoding="utf-8"))
    assert data["table"]["name"] == f"{SESSION}-abrdf-prior.exr"
    np.testing.assert_array_equal(
        table_of(export["page"].read_text(encoding="utf-8")),
        tabulate(VELVET.evaluate).astype("<f4"))
    assert data["material"]["name"] == f"{SESSION}-material.json"
    assert data["material"]["model"] == "ggx+sheen"


def test_maps_folder_in_the_export_gets_its_page(export):
    data = page_data(export["maps_page"].read_text(encoding="utf-8"))
    assert data["maps"]["name"] == "felt-maps" and data["table"] is None


def test_maps_dir_given_as_the_directory_shows_its_maps(export, tmp_path):
    output = tmp_path / "maps.html"
    assert viewer.run([str(export["dir"] / "felt-maps"), "-o", str(output),
                       "--panel-size", PANEL]) == 0
    assert page_data(output.read_text(encoding="utf-8"))["maps"]["name"] == "felt-maps"


def test_a_staging_folder_left_by_a_killed_texture_fit_is_not_a_maps_folder(tmp_path):
    # io::replaceFileSet writes the set into .svbrdf-export.partial first; a fit killed before the
    # swap leaves it, with a maps.json of a set that was never put in place.
    staging = tmp_path / "maps" / ".svbrdf-export.partial"
    staging.mkdir(parents=True)
    (staging / "maps.json").write_text("{}")
    with pytest.raises(SlicecapFileError, match="nothing to show"):
        find_contents(tmp_path / "maps")


def test_folder_of_slicecap_fit_shows_its_table_and_fit_by_name(tmp_path, capsys):
    cli = find_slicecap_cli()
    table, fit = tmp_path / "satin.exr", tmp_path / "satin.json"
    subprocess.run([cli, "generate", "satin-blue-45", "-o", table], check=True,
                   capture_output=True)
    subprocess.run([cli, "fit", table, "-o", fit], check=True, capture_output=True)
    output = tmp_path / "out" / "view.html"
    output.parent.mkdir()
    assert viewer.run([str(tmp_path), "-o", str(output), "--panel-size", PANEL]) == 0
    data = page_data(output.read_text(encoding="utf-8"))
    assert data["table"]["name"] == "satin.exr" and data["material"]["name"] == "satin.json"
    assert "no export manifest" not in capsys.readouterr().err


# ---- bad input: exit 1 naming the file, nothing written ----

def _refused(directory, tmp_path, capsys, named, message):
    output = tmp_path / "view.html"
    assert viewer.run([str(directory), "-o", str(output), "--panel-size", PANEL]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"slicecap.viewer: {named}") and message in err, err
    assert not output.exists()


def test_empty_directory_is_refused_naming_it(tmp_path, capsys):
    empty = tmp_path / "empty"
    empty.mkdir()
    _refused(empty, tmp_path, capsys, f"{empty}: nothing to show", "*-manifest.json or *.exr")


def test_corrupt_table_in_the_export_is_refused_naming_it(tmp_path, capsys):
    directory = write_export(tmp_path / "e")
    table = directory / f"{SESSION}-abrdf-prior.exr"
    table.write_bytes(table.read_bytes()[:200])
    _refused(directory, tmp_path, capsys, table, "EXR")


def test_material_that_is_not_a_fit_is_refused_naming_it(tmp_path, capsys):
    directory = write_export(tmp_path / "e")
    material = directory / f"{SESSION}-material.json"
    material.write_text(json.dumps({"format": "slicecap-session"}))
    _refused(directory, tmp_path, capsys, material, "not a completed slicecap fit")


def test_manifest_naming_a_missing_file_is_refused_naming_it(tmp_path, capsys):
    directory = write_export(tmp_path / "e")
    (directory / f"{SESSION}-abrdf-prior.exr").unlink()
    _refused(directory, tmp_path, capsys, directory / f"{SESSION}-manifest.json",
             f"lists {SESSION}-abrdf-prior.exr, which is not in")


def test_tables_without_a_manifest_are_refused_naming_them(tmp_path, capsys):
    directory = write_export(tmp_path / "e")
    (directory / f"{SESSION}-manifest.json").unlink()
    _refused(directory, tmp_path, capsys, directory, f"{SESSION}-abrdf-b.exr, ")


def test_material_with_a_directory_is_bad_usage(export, capsys):
    material = str(export["dir"] / f"{SESSION}-material.json")
    assert viewer.run([str(export["dir"]), "--material", material, "-o", "x.html"]) == 2
    assert "a directory's fit is found in it" in capsys.readouterr().err


# ---- --serve ----

def _fetch(url):
    with urllib.request.urlopen(url, timeout=30) as response:
        return response.read()


def _as_a_terminals_foreground_job():
    # A test run started as a background job of a non-interactive shell (`scripts/test &`)
    # inherits SIGINT ignored and would pass that on: Python then never raises KeyboardInterrupt,
    # and the server ignores the test's Ctrl-C. A user's Ctrl-C reaches a foreground process.
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start_serving(export, tmp_path, output, preexec_fn=_as_a_terminals_foreground_job):
    """The viewer serving `export` as a process of its own; its stderr goes to a file, not to a
    pipe nobody reads (a full pipe would hold the process), and the stdout lines up to the one
    that says how to stop it are returned with it, so the test acts only once it is ready."""
    package_root = os.path.dirname(os.path.dirname(slicecap.__file__))
    env = {**os.environ, "PYTHONPATH": package_root}
    stderr = open(tmp_path / "serve.stderr", "w")
    process = subprocess.Popen(
        [sys.executable, "-m", "slicecap.viewer", str(export["dir"]), "-o", str(output),
         "--panel-size", PANEL, "--serve"],
        stdout=subprocess.PIPE, stderr=stderr, text=True, env=env, preexec_fn=preexec_fn)
    stderr.close()
    urls = []
    for line in process.stdout:
        if line.startswith("serving "):
            urls.append(line.split()[1])
        if line.startswith("Ctrl-C"):
            return process, urls, line.strip()
    raise AssertionError("the server ended before saying how to stop it: "
                         + (tmp_path / "serve.stderr").read_text())


def _stops_on(process, signum, tmp_path):
    process.send_signal(signum)
    rest = process.stdout.read()  # to the end: the process has closed its stdout
    assert process.wait(timeout=60) == 0, (tmp_path / "serve.stderr").read_text()
    assert rest.splitlines() == ["stopped"], rest


def test_serve_gives_the_written_pages_and_stops_on_ctrl_c(export, tmp_path):
    output = tmp_path / "view.html"
    process, urls, how_to_stop = _start_serving(export, tmp_path, output)
    try:
        assert how_to_stop == "Ctrl-C stops the server"
        assert [u.rsplit("/", 1)[1] for u in urls] == ["", "felt-maps.html"], urls
        assert all(u.startswith("http://127.0.0.1:") for u in urls)
        assert _fetch(urls[0]) == output.read_bytes()
        assert _fetch(urls[1]) == (tmp_path / "view-felt-maps.html").read_bytes()
        with pytest.raises(urllib.error.HTTPError) as missing:
            _fetch(urls[0] + "etc/passwd")
        assert missing.value.code == 404
        # A browser keeps a connection open without a request on it (a preconnect, an idle
        # keep-alive): that may not hold the exit. The page fetched after it is answered only once
        # the server has taken the held connection (it takes them in order), so Ctrl-C comes while
        # a request thread waits on it.
        port = int(urls[0].rsplit(":", 1)[1].split("/", 1)[0])
        with socket.create_connection(("127.0.0.1", port), timeout=30):
            assert _fetch(urls[0]) == output.read_bytes()
            _stops_on(process, signal.SIGINT, tmp_path)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_serve_started_with_ctrl_c_ignored_says_so_and_stops_on_sigterm(export, tmp_path):
    def as_a_background_job():
        signal.signal(signal.SIGINT, signal.SIG_IGN)

    process, _, how_to_stop = _start_serving(export, tmp_path, tmp_path / "view.html",
                                             preexec_fn=as_a_background_job)
    try:
        assert how_to_stop == f"Ctrl-C is ignored (started with SIGINT ignored, as a background " \
                              f"job is): kill {process.pid} stops the server"
        _stops_on(process, signal.SIGTERM, tmp_path)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_server_binds_loopback_on_a_free_port():
    pages = {"/": b"<html></html>"}
    server = make_server(pages)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        host, port = server.server_address[:2]
        assert host == "127.0.0.1" and port > 0
        assert _fetch(f"http://127.0.0.1:{port}/") == pages["/"]
    finally:
        server.shutdown()
        server.server_close()


@pytest.mark.parametrize("host", ["0.0.0.0", "192.168.1.20", "::", "localhost", "example.org"])
def test_server_refuses_anything_but_loopback(host):
    with pytest.raises(ValueError, match="not a loopback address"):
        make_server({"/": b""}, 0, host)


def test_serve_port_out_of_range_is_bad_usage(export, capsys):
    assert viewer.run([str(export["dir"]), "--serve", "70000"]) == 2
    assert "--serve PORT must be in 0..65535" in capsys.readouterr().err


def test_neither_output_nor_serve_is_bad_usage(export, capsys):
    assert viewer.run([str(export["dir"])]) == 2
    assert "give -o VIEW.html, --serve [PORT] or both" in capsys.readouterr().err



def test_texture_without_maps_says_how_to_make_them(tmp_path, capsys):
    directory = write_export(tmp_path / "e")
    assert viewer.run([str(directory), "-o", str(tmp_path / "v.html"), "--panel-size",
                       PANEL]) == 0
    out = capsys.readouterr().out
    assert f"slicecap btf {directory / (SESSION + '-texture')} -o BTF" in out, out
    assert not (tmp_path / f"v-{SESSION}-maps.html").exists()


def test_exports_of_two_sessions_in_one_folder_are_refused_naming_it(tmp_path, capsys):
    directory = write_export(tmp_path / "e")
    write_export(directory, session="silk")
    _refused(directory, tmp_path, capsys, directory,
             "several sessions (felt-manifest.json, silk-manifest.json)")
