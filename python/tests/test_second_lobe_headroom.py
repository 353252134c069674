"""The second-lobe prototype (python/checks/second_lobe_headroom.py): its numpy model is the C++
fit's (checked against `slicecap generate` of a fit, with and without sheen), and its refit finds a
second lobe that is really there. Built-in materials only: the measured tables are not in the
repository."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import REPOSITORY

sys.path.insert(0, str(REPOSITORY / "python" / "checks"))
import second_lobe_headroom as slh  # noqa: E402


def fit_builtin(cli, material, folder):
    table, fit = folder / f"{material}.f32", folder / f"{material}.json"
    subprocess.run([cli, "generate", material, "-o", table], check=True, capture_output=True)
    subprocess.run([cli, "fit", table, "-o", fit], check=True, capture_output=True)
    return fit


# brushed-steel-30 fits as plain GGX with a turned tangent; velvet-green-20 as ggx+sheen, so both
# branches of the model and the tangent's rotation are compared.
@pytest.mark.parametrize("material, model", [("brushed-steel-30", "ggx"),
                                             ("velvet-green-20", "ggx+sheen")])
def test_numpy_model_matches_slicecap_generate(slicecap_cli, tmp_path, material, model):
    fit = fit_builtin(slicecap_cli, material, tmp_path)
    assert json.loads(fit.read_text())["model"] == model
    mismatch = slh.model_mismatch(slicecap_cli, fit, slh.grid_geometry())
    assert mismatch <= 1e-5


def coated_table(cli, tmp_path):
    """A rough red base under a sharper grey coat (f0 0.04, f90 1, alpha 0.06): a table the
    two-lobe family, and its --coat subfamily, hold exactly; with its one-lobe fit (no coat: the
    prototype measures what a second lobe adds to the fit of one)."""
    g = slh.grid_geometry()
    truth = np.zeros(15)
    truth[0:3] = (0.4, 0.05, 0.05)
    truth[3:6] = (0.3, 0.05, 0.05)
    truth[6] = 0.5
    truth[7] = truth[8] = 0.35
    truth[10:13] = 0.04
    truth[13] = 1.0
    truth[14] = 0.06
    table = tmp_path / "coated.f32"
    slh.write_f32(table, slh.tabulate(g, truth, with_sheen=False))
    fit = tmp_path / "coated.json"
    subprocess.run([cli, "fit", table, "-o", fit, "--no-sheen", "--no-coat"], check=True,
                   capture_output=True)
    return g, table, fit


def test_refit_finds_a_clear_coat_the_one_lobe_fit_misses(slicecap_cli, tmp_path):
    g, table, fit = coated_table(slicecap_cli, tmp_path)
    one_lobe_delta_e = json.loads(fit.read_text())["metrics"]["delta_e"]

    best = slh.fit_two_lobes(g, slh.read_f32(table), fit, max_iterations=100)
    refit = tmp_path / "refit.f32"
    slh.write_f32(refit, slh.tabulate(g, best["p"], best["with_sheen"]))
    two_lobe_delta_e = slh.compare_delta_e(slicecap_cli, table, refit)

    assert one_lobe_delta_e > 0.5, "the coat must be something one lobe cannot say"
    assert two_lobe_delta_e < 0.1 * one_lobe_delta_e
    # Either lobe may end up as the coat: the sharper one must be the truth's.
    alphas = sorted([best["p"][7], best["p"][14]])
    assert math.isclose(alphas[0], 0.06, rel_tol=0.1)


def test_coat_mode_recovers_a_grey_coat_with_f90_one(slicecap_cli, tmp_path):
    g, table, fit = coated_table(slicecap_cli, tmp_path)

    best = slh.fit_two_lobes(g, slh.read_f32(table), fit, max_iterations=100, coat=True)
    p = best["p"]
    assert p[10] == p[11] == p[12] and p[13] == 1.0
    refit = tmp_path / "refit.f32"
    slh.write_f32(refit, slh.tabulate(g, p, best["with_sheen"]))
    one_lobe_delta_e = json.loads(fit.read_text())["metrics"]["delta_e"]
    assert slh.compare_delta_e(slicecap_cli, table, refit) < 0.1 * one_lobe_delta_e
    assert math.isclose(p[14], 0.06, rel_tol=0.1)
    assert math.isclose(p[10], 0.04, rel_tol=0.1)


@pytest.mark.parametrize("model", ["ggx+coat", "ggx+sheen+coat"])
def test_a_coated_fit_is_refused_naming_it(tmp_path, capsys, model):
    """A fit whose coat already is a second lobe, layered where the prototype's is added: refused
    before anything runs (the CLI given does not exist), exit 1 naming the fit."""
    fits = tmp_path / "fits"
    fits.mkdir()
    parameters = {"diffuse_albedo": [0.2, 0.1, 0.1], "specular_f0": [0.04] * 3,
                  "specular_f90": 1.0, "alpha_tangent": 0.3, "alpha_bitangent": 0.3,
                  "tangent_deg": 0.0, "sheen_colour": [0.1] * 3, "sheen_roughness": 0.4,
                  "coat_weight": 0.8, "coat_alpha": 0.05}
    (fits / "coated.json").write_text(json.dumps({
        "format": "slicecap-material", "format_version": 1, "model": model,
        "parameters": {n: {"value": v, "sigma": None, "unit": "-"} for n, v in parameters.items()},
        "metrics": {"delta_e": 2.0}}))
    (fits / "summary.tsv").write_text("table\tmodel\tlobe\tdelta_e\ncoated\t" + model
                                      + "\tisotropic\t2.0\n")
    code = slh.main(["--cli", str(tmp_path / "no-such-slicecap"), "--tables", str(tmp_path),
                     "--fits", str(fits), "--out", str(tmp_path / "out")])
    assert code == 1
    err = capsys.readouterr().err
    assert f"{fits / 'coated.json'}: model {model} has a clear coat" in err, err
