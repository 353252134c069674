"""The SVBRDF maps of `slicecap fit BTF_DIR -o MAPS` (docs/material-fit.md, "Texture mode"): the
textured glTF, with its PNG maps loaded as external resources, passes the Khronos glTF validator
(npm gltf-validator, scripts/consumers-install) with no errors and no warnings; maps.json names
every texel not fitted (the C++ tests check the maps' pixels). The validator test skips with its
reason when the validator is not installed."""

import json
import shutil
import subprocess

import pytest
from conftest import REPOSITORY

CONSUMERS = REPOSITORY / "tools" / "consumers"
VALIDATOR = CONSUMERS / "node_modules" / "gltf-validator"

# The validator with the glTF's images read from beside it (validate-gltf.mjs refuses external
# resources: the table exports embed theirs).
VALIDATE_WITH_FILES = """
const fs = require("fs"), path = require("path"), validator = require("gltf-validator");
const file = process.argv[1];
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
  uri: path.basename(file), maxIssues: 100,
  externalResourceFunction: (uri) => fs.promises.readFile(
      path.join(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
}).then((report) => console.log(JSON.stringify(report)));
"""


@pytest.fixture(scope="module")
def maps(tmp_path_factory, slicecap_cli_for_module):
    """A simulated woven session, its 4 x 4 BTF and the BTF's maps."""
    root = tmp_path_factory.mktemp("svbrdf")
    cli = str(slicecap_cli_for_module)
    session, btf, out = root / "session", root / "btf", root / "maps"
    subprocess.run([cli, "simulate", "--material", "woven", "--session", session, "--frames",
                    "8", "--ideal"], check=True, capture_output=True)
    subprocess.run([cli, "btf", session, "-o", btf, "--resolution", "4", "--threads", "2"],
                   check=True, capture_output=True)
    subprocess.run([cli, "fit", btf, "-o", out, "--threads", "2"], check=True,
                   capture_output=True)
    return out


def test_textured_gltf_passes_the_khronos_validator(maps):
    node = shutil.which("node")
    if node is None or not VALIDATOR.is_dir():
        pytest.skip("the glTF validator is not installed (node and scripts/consumers-install)")
    run = subprocess.run([node, "-e", VALIDATE_WITH_FILES, maps / "material.gltf"],
                         cwd=CONSUMERS, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    report = json.loads(run.stdout)
    issues = report["issues"]
    assert issues["numErrors"] == 0, issues["messages"]
    assert issues["numWarnings"] == 0, issues["messages"]
    assert {"KHR_materials_anisotropy", "KHR_materials_specular",
            "KHR_materials_ior"} <= set(report["info"]["extensionsUsed"])
    # The validator read the five PNGs it references (a missing one is an IO error above).
    images = [r for r in report["info"]["resources"] if r.get("storage") == "external"
              and r.get("mimeType") == "image/png"]
    assert len(images) == 5, report["info"]["resources"]
    assert all(r["image"]["width"] == r["image"]["height"] == 4 for r in images), images


def test_maps_json_names_every_texel_it_did_not_fit(maps):
    summary = json.loads((maps / "maps.json").read_text())
    assert summary["resolution"] == 4
    assert summary["texels_fitted"] + len(summary["failed_texels"]) == 16
    assert summary["texels_fitted"] > 0
    for texel in summary["failed_texels"]:
        assert texel["problem"].startswith(f"texel ({texel['x']},{texel['y']})"), texel
    # The normal map holds the fitted tilts; a fitted texel left flat is named with the reason.
    assert summary["normal_map"].startswith("fitted")
    flat = summary["flat_normal_texels"]
    assert summary["texels_tilt_fitted"] + len(flat) == summary["texels_fitted"]
    for texel in flat:
        assert texel["normal"].startswith("flat"), texel
