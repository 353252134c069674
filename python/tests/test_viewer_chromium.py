"""The material viewer page in a real browser: Debian's headless Chromium renders the sphere
panels (python/checks/viewer_chromium.py, also `scripts/consumer-check viewer`) and they must
match the numpy renderer's pictures of the same table and fit within its tolerance, with the
turned-tangent control seen, and for the clear-coated material the coat-removed one. About 60 s;
chromium comes with scripts/deps/browser.list."""

import json
import shutil
import subprocess
import sys

import pytest
from conftest import REPOSITORY

CHECK = REPOSITORY / "python" / "checks" / "viewer_chromium.py"
TOLERANCE = 0.5


def test_chromium_spheres_match_the_numpy_renderer(slicecap_cli, tmp_path):
    if shutil.which("chromium") is None:
        pytest.skip("chromium is not installed (Debian's `chromium`, scripts/deps/browser.list): "
                    "the viewer's real-browser check needs it")
    run = subprocess.run(
        [sys.executable, str(CHECK), "--cli", str(slicecap_cli), "--out", str(tmp_path),
         "--tolerance", str(TOLERANCE)],
        capture_output=True, text=True, timeout=600,
    )
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    results = json.loads((tmp_path / "viewer-results.json").read_text(encoding="utf-8"))
    panels = [r for r in results if r["panel"] in ("fit", "table")]
    # Four materials (three built-in, one clear-coated), two views, two panels: a check that
    # compared nothing would pass vacuously.
    assert len(panels) == 16
    assert {r["material"] for r in panels} >= {"coated-blue-satin"}
    assert all(r["delta_e"] <= TOLERANCE for r in panels), panels
    # The turned tangent for each material, and the coat removed for the coated one.
    controls = [r for r in results if r["panel"].startswith("control")]
    assert len(controls) == 5
    assert any(r["panel"] == "control: fit without its coat" and r["delta_e"] > TOLERANCE
               for r in controls)
