"""The Mitsuba 3 BSDF `slicecap`: it evaluates the table as slicecap.evaluate does, renders a
Lambertian table like Mitsuba's `diffuse`, a Phong table like an analytic Phong BSDF, keeps
reciprocity, samples by the density it reports, and fails with the reader's message."""

import numpy as np
import pytest
from mitsuba_support import analytic_phong_bsdf_class, phong, render, sphere_scene, use_variant

from slicecap import evaluate, tabulate, write_abrdf_exr
from slicecap.grid import to_unit_vectors

LLVM = "llvm_ad_rgb"
SCALAR = "scalar_rgb"


def random_directions_deg(rng, n, max_theta_deg=89.0):
    return np.stack([rng.uniform(0.5, max_theta_deg, n), rng.uniform(0, 360, n)], axis=-1)


def random_table(rng) -> np.ndarray:
    return rng.uniform(0.05, 2.0, (81, 81, 3)).astype(np.float32)


def load_plugin(mi, path):
    return mi.load_dict({"type": "slicecap", "filename": str(path)})


def eval_plugin(mi, bsdf, view_deg, light_deg, mode=None):
    """The plugin's BRDF (its eval divided by cos theta of wo) for camera-side `view` directions."""
    import drjit as dr

    view = to_unit_vectors(view_deg)
    light = to_unit_vectors(light_deg)
    ctx = mi.BSDFContext() if mode is None else mi.BSDFContext(mode)
    si = dr.zeros(mi.SurfaceInteraction3f, len(view))
    wi, wo = (view, light) if mode in (None, mi.TransportMode.Radiance) else (light, view)
    si.wi = mi.Vector3f(*(wi[:, i] for i in range(3)))
    value = bsdf.eval(ctx, si, mi.Vector3f(*(wo[:, i] for i in range(3))))
    return np.array(value).reshape(3, -1).T / wo[:, 2:3]


@pytest.fixture
def llvm():
    return use_variant(LLVM)


def test_eval_matches_the_package_interpolation(llvm, tmp_path):
    rng = np.random.default_rng(1)
    table = random_table(rng)
    write_abrdf_exr(tmp_path / "random.exr", table)
    bsdf = load_plugin(llvm, tmp_path / "random.exr")
    light_deg = random_directions_deg(rng, 4000)
    view_deg = random_directions_deg(rng, 4000)
    got = eval_plugin(llvm, bsdf, view_deg, light_deg)
    expected = evaluate(table, light_deg, view_deg)
    np.testing.assert_allclose(got, expected, rtol=2e-4)


def test_rows_are_lights_in_radiance_and_importance_modes(llvm, tmp_path):
    # A table that depends on the light only: swapping light and view would show at once.
    table = np.repeat(np.linspace(0.1, 8.1, 81, dtype=np.float32)[:, None, None], 81, axis=1)
    table = np.repeat(table, 3, axis=2)
    write_abrdf_exr(tmp_path / "light-only.exr", table)
    bsdf = load_plugin(llvm, tmp_path / "light-only.exr")
    rng = np.random.default_rng(2)
    light_deg = random_directions_deg(rng, 500)
    view_deg = random_directions_deg(rng, 500)
    expected = evaluate(table, light_deg, view_deg)
    for mode in (llvm.TransportMode.Radiance, llvm.TransportMode.Importance):
        np.testing.assert_allclose(
            eval_plugin(llvm, bsdf, view_deg, light_deg, mode), expected, rtol=2e-4
        )


def test_reciprocal_input_stays_reciprocal(llvm, tmp_path):
    rng = np.random.default_rng(3)
    table = random_table(rng)
    table = 0.5 * (table + np.transpose(table, (1, 0, 2)))
    write_abrdf_exr(tmp_path / "reciprocal.exr", table)
    bsdf = load_plugin(llvm, tmp_path / "reciprocal.exr")
    a = random_directions_deg(rng, 3000)
    b = random_directions_deg(rng, 3000)
    forward = eval_plugin(llvm, bsdf, a, b)
    backward = eval_plugin(llvm, bsdf, b, a)
    np.testing.assert_allclose(forward, backward, rtol=1e-5)
    # A table that is not reciprocal is not made so (the test above could not pass by accident).
    write_abrdf_exr(tmp_path / "one-way.exr", random_table(rng))
    one_way = load_plugin(llvm, tmp_path / "one-way.exr")
    assert np.max(np.abs(eval_plugin(llvm, one_way, a, b) - eval_plugin(llvm, one_way, b, a))) > 0.1


def test_sampling_reports_its_own_density_and_is_unbiased(llvm, tmp_path):
    import drjit as dr

    mi = llvm
    table = tabulate(phong([0.1, 0.2, 0.3], [0.6, 0.5, 0.4], 20))
    write_abrdf_exr(tmp_path / "phong.exr", table)
    bsdf = load_plugin(mi, tmp_path / "phong.exr")
    n = 400_000
    ctx = mi.BSDFContext()
    for view_deg in ([0.0, 0.0], [40.0, 100.0], [70.0, 250.0]):
        wi = to_unit_vectors(np.array(view_deg))
        si = dr.zeros(mi.SurfaceInteraction3f, n)
        si.wi = mi.Vector3f(*(float(x) for x in wi))
        sampler = np.random.default_rng(4)
        u1 = mi.Float(sampler.random(n).astype(np.float32))
        u2 = mi.Point2f(*(sampler.random((2, n)).astype(np.float32)))
        bs, weight = bsdf.sample(ctx, si, u1, u2)
        pdf_again = bsdf.pdf(ctx, si, bs.wo)
        np.testing.assert_allclose(np.array(bs.pdf), np.array(pdf_again), rtol=1e-5)
        albedo_sampled = np.array(weight).reshape(3, -1).mean(axis=1)
        # The same integral with uniform hemisphere samples: agreement means the sampler draws
        # from the density it reports.
        uniform = mi.warp.square_to_uniform_hemisphere(u2)
        value = np.array(bsdf.eval(ctx, si, uniform)).reshape(3, -1)
        albedo_uniform = value.mean(axis=1) * 2 * np.pi
        np.testing.assert_allclose(albedo_sampled, albedo_uniform, rtol=0.01)
        # The density integrates to one over the hemisphere.
        pdf_uniform = np.array(bsdf.pdf(ctx, si, uniform))
        assert pdf_uniform.mean() * 2 * np.pi == pytest.approx(1.0, abs=0.01)


def noise_ratio(mi, test_bsdf: dict, reference_bsdf: dict, lights: str) -> tuple[float, float]:
    """(mean squared difference test - reference) / (the same between two reference renders with
    other seeds), and the relative difference of the images' means."""
    test = render(mi, sphere_scene(mi, test_bsdf, lights=lights), seed=1)
    reference = render(mi, sphere_scene(mi, reference_bsdf, lights=lights), seed=2)
    reference_again = render(mi, sphere_scene(mi, reference_bsdf, lights=lights), seed=3)
    noise = np.mean((reference - reference_again) ** 2)
    ratio = np.mean((test - reference) ** 2) / noise
    relative_mean = abs(test.mean() - reference.mean()) / reference.mean()
    return ratio, relative_mean


@pytest.mark.parametrize("lights", ["points", "envmap"])
def test_lambertian_table_renders_like_mitsuba_diffuse(llvm, tmp_path, lights):
    albedo = [0.7, 0.45, 0.2]
    table = np.broadcast_to(np.array(albedo, np.float32) / np.pi, (81, 81, 3))
    write_abrdf_exr(tmp_path / "lambert.exr", table)
    ratio, relative_mean = noise_ratio(
        llvm,
        {"type": "slicecap", "filename": str(tmp_path / "lambert.exr")},
        {"type": "diffuse", "reflectance": {"type": "rgb", "value": albedo}},
        lights,
    )
    # Only Monte Carlo noise: the plugin's noise is no larger than diffuse's own (ratio ~ 1).
    assert ratio < 1.3, ratio
    assert relative_mean < 0.005, relative_mean


@pytest.mark.parametrize("lights", ["points", "envmap"])
def test_phong_table_renders_like_an_analytic_phong_bsdf(llvm, tmp_path, lights):
    kd, ks, exponent = [0.3, 0.15, 0.05], [0.25, 0.25, 0.25], 3
    write_abrdf_exr(tmp_path / "phong.exr", tabulate(phong(kd, ks, exponent)))
    llvm.register_bsdf("analytic_phong", analytic_phong_bsdf_class(llvm, kd, ks, exponent))

    def image(bsdf):
        # One seed for both: the camera rays and light samples coincide, so what differs is the
        # BSDF (and, under the environment, the sampling of its reflected rays).
        return render(llvm, sphere_scene(llvm, bsdf, lights=lights, spp=128), seed=1)

    test = image({"type": "slicecap", "filename": str(tmp_path / "phong.exr")})
    reference = image({"type": "analytic_phong"})
    # The table is the lobe sampled every 15 deg and interpolated linearly: 2.7 % (up to 4.8 %
    # with grazing angles) cos-weighted relative RMSE of the BRDF over the hemisphere. Measured
    # on the renderings: 3.6 % under the point lights, 1.2 % under the environment.
    relative_rmse = np.sqrt(np.mean((test - reference) ** 2) / np.mean(reference**2))
    relative_mean = abs(test.mean() - reference.mean()) / reference.mean()
    assert relative_rmse < 0.05, relative_rmse
    assert relative_mean < 0.01, relative_mean


def test_lambertian_table_under_point_lights_is_diffuse_to_float_precision(llvm, tmp_path):
    albedo = [0.7, 0.45, 0.2]
    write_abrdf_exr(
        tmp_path / "lambert.exr", np.broadcast_to(np.array(albedo, np.float32) / np.pi, (81, 81, 3))
    )
    test = render(
        llvm,
        sphere_scene(
            llvm, {"type": "slicecap", "filename": str(tmp_path / "lambert.exr")}, lights="points"
        ),
        seed=1,
    )
    reference = render(
        llvm,
        sphere_scene(
            llvm,
            {"type": "diffuse", "reflectance": {"type": "rgb", "value": albedo}},
            lights="points",
        ),
        seed=1,
    )
    np.testing.assert_allclose(test, reference, rtol=1e-4, atol=1e-6)


def test_malformed_exr_gives_the_readers_error(llvm, tmp_path):
    import OpenEXR

    header = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
        "slicecap:layout": "bonn81",
        "slicecap:quantity": "brdf",
    }
    pixels = {c: np.zeros((81, 81), np.float32) for c in "RG"}
    with OpenEXR.File(header, pixels) as file:
        file.write(str(tmp_path / "rg.exr"))
    with pytest.raises(Exception, match=r"rg\.exr: ABRDF EXR has no channel B \(needs R, G, B\)"):
        load_plugin(llvm, tmp_path / "rg.exr")
    with pytest.raises(Exception, match="property 'filename'"):
        llvm.load_dict({"type": "slicecap"})


def test_a_relative_filename_in_a_scene_file_is_the_scene_folders(llvm, tmp_path, monkeypatch):
    # As Mitsuba's own plugins: a scene file's "satin.exr" is the one beside it, not whatever
    # the working folder holds under that name.
    table = random_table(np.random.default_rng(6))
    (tmp_path / "scene").mkdir()
    write_abrdf_exr(tmp_path / "scene" / "satin.exr", table, {"material": "beside-the-scene"})
    write_abrdf_exr(tmp_path / "satin.exr", table, {"material": "in-the-working-folder"})
    (tmp_path / "scene" / "scene.xml").write_text(
        '<scene version="3.0.0"><shape type="sphere">'
        '<bsdf type="slicecap"><string name="filename" value="satin.exr"/></bsdf>'
        "</shape></scene>"
    )
    monkeypatch.chdir(tmp_path)
    scene = llvm.load_file(str(tmp_path / "scene" / "scene.xml"))
    assert "beside-the-scene" in str(scene.shapes()[0].bsdf())
    monkeypatch.chdir(tmp_path / "scene")
    (tmp_path / "satin.exr").unlink()
    assert "beside-the-scene" in str(llvm.load_file("scene.xml").shapes()[0].bsdf())


def test_scalar_variant_evaluates_and_samples_like_llvm(tmp_path):
    rng = np.random.default_rng(5)
    table = random_table(rng)
    write_abrdf_exr(tmp_path / "random.exr", table)
    light_deg = random_directions_deg(rng, 20)
    view_deg = random_directions_deg(rng, 20)
    expected = evaluate(table, light_deg, view_deg)
    mi = use_variant(SCALAR)
    bsdf = load_plugin(mi, tmp_path / "random.exr")
    ctx = mi.BSDFContext()
    import drjit as dr

    for k in range(len(light_deg)):
        si = dr.zeros(mi.SurfaceInteraction3f)
        view, light = to_unit_vectors(view_deg[k]), to_unit_vectors(light_deg[k])
        si.wi = mi.Vector3f(*(float(x) for x in view))
        value = np.array(bsdf.eval(ctx, si, mi.Vector3f(*(float(x) for x in light)))) / light[2]
        np.testing.assert_allclose(value, expected[k], rtol=2e-4)
        bs, weight = bsdf.sample(ctx, si, 0.37, mi.Point2f(0.21, 0.66))
        assert bs.pdf > 0 and bs.wo.z > 0
        np.testing.assert_allclose(bs.pdf, bsdf.pdf(ctx, si, bs.wo), rtol=1e-5)
    image = render(
        mi,
        sphere_scene(
            mi, {"type": "slicecap", "filename": str(tmp_path / "random.exr")}, size=8, spp=4
        ),
    )
    assert np.all(np.isfinite(image)) and image.mean() > 0


def test_a_variant_that_is_not_rgb_is_refused_when_registering():
    import slicecap.mitsuba_bsdf

    mi = pytest.importorskip("mitsuba", reason="mitsuba is not installed")
    if "scalar_spectral" not in mi.variants():
        pytest.skip("this Mitsuba build has no scalar_spectral variant")
    mi.set_variant("scalar_spectral")
    # Registered there, the plugin loaded and then failed in mi.render with std::bad_cast.
    with pytest.raises(RuntimeError, match="variant scalar_spectral is not an RGB variant"):
        slicecap.mitsuba_bsdf.register()
