"""brdfkit.model, fit and energy: the library's numbers, equal to the CLI's bit for bit."""
import json

import numpy as np
import pytest

import brdfkit
from conftest import cli_json, without_times

GGX = "ggx:rho_d=0.2,0.3,0.4:f0=0.04:alpha=0.1"


def random_directions(rng, count):
    directions = rng.normal(size=(count, 3))
    directions[:, 2] = np.abs(directions[:, 2])
    return directions / np.linalg.norm(directions, axis=1, keepdims=True)


def test_model_string_and_params():
    model = brdfkit.model(GGX)
    assert model.name == "ggx"
    assert model.params == {"rho_d": [0.2, 0.3, 0.4], "f0": [0.04, 0.04, 0.04], "alpha": 0.1}
    assert brdfkit.model(model.string).params == model.params
    assert "ggx" in [entry["name"] for entry in brdfkit.models()]


def test_lambert_eval_is_rho_over_pi_and_reciprocal():
    rng = np.random.default_rng(1)
    wi, wo = random_directions(rng, 1000), random_directions(rng, 1000)
    lambert = brdfkit.model("lambert:rho_d=0.3,0.6,0.9")
    np.testing.assert_allclose(lambert.eval(wi, wo), np.tile([0.3, 0.6, 0.9], (1000, 1)) / np.pi,
                               rtol=1e-15)
    ggx = brdfkit.model(GGX)
    np.testing.assert_allclose(ggx.eval(wi, wo), ggx.eval(wo, wi), rtol=1e-14, atol=0)
    # One (3,) direction is used for every row.
    np.testing.assert_array_equal(ggx.eval(wi[0], wo), ggx.eval(np.tile(wi[0], (1000, 1)), wo))
    assert ggx.eval(wi[0], wo[0]).shape == (3,)


def test_model_eval_equals_the_renderer_at_random_directions(brdf, tmp_path):
    # Under one directional light the renderer's pixel is exactly f(wi, wo) E cos(theta_i) in
    # each pixel's shading frame (src/render/sphere.h): the C++ model at the directions the
    # sphere's normals give, which differ from pixel to pixel.
    spec, size = "blinn-phong:rho_d=0.1,0.2,0.3:rho_s=0.5:m=40", 24
    rng = np.random.default_rng(7)
    theta, phi = rng.uniform(10, 60), rng.uniform(0, 360)
    light = f"dir:theta={theta!r}:phi={phi!r}:rgb=1,1,1"
    brdf("render", spec, "--light", light, "--size", size, "--exr", tmp_path / "r.exr",
         "--exr-type", "float", "--out", tmp_path / "r.png", "--quiet")
    rendered = brdfkit.read_hdr(str(tmp_path / "r.exr"))
    t, p = np.radians(theta), np.radians(phi)
    light_dir = np.array([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)])
    wi, wo, cos_i, pixels = [], [], [], []
    for y in range(size):
        for x in range(size):
            u, v = (2 * x + 1) / size - 1, 1 - (2 * y + 1) / size
            if u * u + v * v >= 1:
                continue
            n = np.array([u, v, np.sqrt(1 - u * u - v * v)])
            # Duff et al. 2017, as core/sampling.h's Frame::FromZ.
            sign = np.copysign(1.0, n[2])
            a = -1.0 / (sign + n[2])
            b = n[0] * n[1] * a
            frame = np.array([[1 + sign * n[0] * n[0] * a, sign * b, -sign * n[0]],
                              [b, sign + n[1] * n[1] * a, -n[1]], n])
            local_i, local_o = frame @ light_dir, frame @ np.array([0.0, 0.0, 1.0])
            if local_i[2] <= 0:
                continue
            wi.append(local_i)
            wo.append(local_o)
            cos_i.append(local_i[2])
            pixels.append(rendered[y, x, :3])
    assert len(pixels) > 100
    f = brdfkit.model(spec).eval(np.array(wi), np.array(wo))
    expected = (f * np.array(cos_i)[:, None]).astype(np.float32)
    np.testing.assert_allclose(np.array(pixels), expected, rtol=1e-6, atol=0)


def test_fit_equals_brdf_fit(brdf, data_dir, tmp_path):
    source = str(data_dir / "cornell-astm" / "cayman.astm")
    fit = brdfkit.fit(brdfkit.read(source), model="blinn-phong", loss="log", max_samples=500,
                      threads=1)
    cli = cli_json(brdf("fit", source, "--model", "blinn-phong", "--loss", "log",
                        "--max-samples", 500, "--json"))
    assert without_times(fit.report) == cli
    assert fit.model.string == cli["model_string"]
    assert fit.params == cli["params"] and fit.stderr == cli["stderr"]
    assert fit.metrics == cli["metrics"]
    assert fit.converged
    # The fitted model as a fit report reads back as the same model.
    (tmp_path / "fit.json").write_text(json.dumps(fit.report))
    assert brdfkit.model(str(tmp_path / "fit.json")).string == fit.model.string
    rng = np.random.default_rng(3)
    wi, wo = random_directions(rng, 50), random_directions(rng, 50)
    np.testing.assert_array_equal(fit.eval(wi, wo), fit.model.eval(wi, wo))


def test_auto_fit_keeps_the_chosen_candidates_fit(brdf, tmp_path):
    # `brdf fit --model auto` itself is tested against the selection in the C++ suite; here the
    # module's auto path: the report carries the selection, and the chosen fit is the named fit.
    brdf("measure", "--sample", "model:blinn-phong:rho_d=0.3:rho_s=0.2:m=50", "--schedule",
         "inplane:step=10", "--out", tmp_path / "bp.csv", "--quiet")
    source = str(tmp_path / "bp.csv")
    fit = brdfkit.fit(source, max_iterations=50)
    selection = fit.report["selection"]
    assert selection["chosen"] == fit.model.name
    ladder = [e["name"] for e in brdfkit.models() if e["auto"]]
    assert [c["model"] for c in selection["candidates"]] == ladder
    named = brdfkit.fit(source, model=fit.model.name, max_iterations=50)
    assert fit.model.string == named.model.string
    assert without_times(fit.report) == dict(without_times(named.report),
                                              selection=without_times(selection))


def test_energy_of_a_model_equals_brdf_energy(brdf):
    energy = brdfkit.energy(brdfkit.model(GGX), theta_steps=12)
    cli = cli_json(brdf("energy", GGX, "--theta-steps", 12, "--json", "--quiet"))
    assert without_times(energy.report) == cli
    assert energy.albedo.shape == energy.error.shape == (12, 3)
    np.testing.assert_array_equal(energy.theta_deg, [p["theta_deg"] for p in cli["albedo"]])
    np.testing.assert_array_equal(energy.albedo, [p["rgb"] for p in cli["albedo"]])
    np.testing.assert_array_equal(energy.max, cli["max_albedo"])
    assert energy.verdict == cli["verdict"] == "conserving"
    assert energy.reason == cli["reason"]


def test_lambert_albedo_is_rho():
    energy = brdfkit.energy("lambert:rho_d=0.3,0.5,0.7", theta_steps=5)
    np.testing.assert_allclose(energy.albedo, np.tile([0.3, 0.5, 0.7], (5, 1)), rtol=1e-9)
    mc = brdfkit.energy("lambert:rho_d=0.5", method="mc", theta_steps=3, samples=4096, seed=2)
    assert np.all(np.abs(mc.albedo - 0.5) <= 4 * mc.error + 1e-12)


def test_energy_of_a_measurement_and_of_a_fit_equal_brdf_energy(brdf, data_dir, tmp_path):
    source = str(data_dir / "rgl-bsdf" / "paper_white_rgb.bsdf")
    energy = brdfkit.energy(brdfkit.read(source), theta_steps=6, threads=1)
    cli = cli_json(brdf("energy", source, "--theta-steps", 6, "--json", "--quiet"))
    assert without_times(energy.report) == cli

    fit = brdfkit.fit(str(data_dir / "cornell-astm" / "cayman.astm"), model="lambert")
    (tmp_path / "fit.json").write_text(json.dumps(fit.report))
    energy = brdfkit.energy(fit, theta_steps=4)
    cli = cli_json(brdf("energy", tmp_path / "fit.json", "--theta-steps", 4, "--json", "--quiet"))
    assert without_times(energy.report) == without_times(cli)
