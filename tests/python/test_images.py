"""brdfkit.render, tonemap and measure: the same floats and bytes as the CLI's outputs."""
import numpy as np
from PIL import Image

import brdfkit

SPEC = "ggx:rho_d=0.3,0.2,0.1:f0=0.9:alpha=0.2"


def png_pixels(path):
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"))


def test_render_equals_brdf_render_exr(brdf, data_dir, tmp_path):
    env = str(data_dir / "hdr" / "memorial.hdr")
    image = brdfkit.render(brdfkit.model(SPEC), env=env, size=32, spp=4, seed=3)
    assert image.dtype == np.float32 and image.shape == (32, 32, 4)
    brdf("render", SPEC, "--env", env, "--size", 32, "--spp", 4, "--seed", 3, "--exr",
         tmp_path / "cli.exr", "--exr-type", "float", "--out", tmp_path / "cli.png", "--quiet")
    np.testing.assert_array_equal(image, brdfkit.read_hdr(str(tmp_path / "cli.exr")))
    # The preview's PNG is the tone pipeline's default on that image.
    np.testing.assert_array_equal(brdfkit.tonemap(image), png_pixels(tmp_path / "cli.png"))
    # Alpha marks the sphere; the result does not depend on the thread count.
    assert image[16, 16, 3] == 1 and image[0, 0, 3] == 0
    np.testing.assert_array_equal(
        brdfkit.render(SPEC, env=env, size=32, spp=4, seed=3, threads=1), image)


def test_render_of_a_fit_and_lights_equals_brdf_render(brdf, data_dir, tmp_path):
    fit = brdfkit.fit(str(data_dir / "cornell-astm" / "cayman.astm"), model="blinn-phong",
                      max_samples=500)
    (tmp_path / "fit.json").write_text(__import__("json").dumps(fit.report))
    image = brdfkit.render(fit, light=["dir:theta=30:phi=10:lux=1000"], preset="cloudy",
                           size=24)
    brdf("render", tmp_path / "fit.json", "--light", "dir:theta=30:phi=10:lux=1000", "--preset",
         "cloudy", "--size", 24, "--exr", tmp_path / "cli.exr", "--exr-type", "float",
         "--out", tmp_path / "cli.png", "--quiet")
    np.testing.assert_array_equal(image, brdfkit.read_hdr(str(tmp_path / "cli.exr")))


def test_tonemap_equals_brdf_tonemap(brdf, data_dir, tmp_path):
    source = str(data_dir / "hdr" / "memorial.exr")
    brdf("tonemap", source, "--operator", "reinhard", "--bloom", "dual", "--ev", -1, "--out",
         tmp_path / "cli.png", "--quiet")
    expected = png_pixels(tmp_path / "cli.png")
    toned = brdfkit.tonemap(brdfkit.read_hdr(source), operator="reinhard", bloom="dual", ev=-1)
    assert toned.dtype == np.uint8 and toned.shape == expected.shape
    np.testing.assert_array_equal(toned, expected)
    np.testing.assert_array_equal(
        brdfkit.tonemap(source, operator="reinhard", bloom="dual", ev=-1), expected)
    # Options as numbers or as the CLI's text are the same option.
    brdf("tonemap", source, "--exposure", 0.3, "--white", 4, "--gamma", 2.2, "--out",
         tmp_path / "cli2.png", "--quiet")
    np.testing.assert_array_equal(brdfkit.tonemap(source, exposure=0.3, white=4, gamma=2.2),
                                  png_pixels(tmp_path / "cli2.png"))


def test_tonemap_of_rgb_without_alpha_and_of_bad_pixels():
    rgb = np.full((8, 8, 3), 0.25, dtype=np.float32)
    rgba = np.concatenate([rgb, np.ones((8, 8, 1), np.float32)], axis=2)
    np.testing.assert_array_equal(brdfkit.tonemap(rgb, exposure=1, operator="none"),
                                  brdfkit.tonemap(rgba, exposure=1, operator="none"))
    # sRGB of 0.25 is 0.537: 137 in 8 bits (IEC 61966-2-1).
    assert np.all(brdfkit.tonemap(rgb, exposure=1, operator="none") == 137)
    rgb[0, 0, 0] = np.nan
    with __import__("pytest").warns(UserWarning, match="1 pixels with NaN"):
        brdfkit.tonemap(rgb, exposure=1, operator="none")


def test_measure_equals_brdf_measure(brdf, tmp_path):
    sample = "model:blinn-phong:rho_d=0.3:rho_s=0.1:m=100"
    schedule = "hemisphere:theta_i_step=30:theta_o_step=20:phi_o_step=60"
    measurement = brdfkit.measure(sample, schedule=schedule, seed=4)
    measurement.save(str(tmp_path / "python.csv"))
    brdf("measure", "--sample", sample, "--schedule", schedule, "--seed", 4, "--out",
         tmp_path / "cli.csv", "--quiet")
    assert (tmp_path / "python.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    assert measurement.sigma is not None and measurement.metadata["seed"] == "4"
    np.testing.assert_array_equal(
        brdfkit.measure(sample, schedule=schedule, seed=4, threads=1).rgb, measurement.rgb)


def test_sphere_measure_equals_brdf_measure(brdf, tmp_path):
    sample = "sphere:blinn-phong:rho_d=0.3:rho_s=0.1:m=100"
    instrument = tmp_path / "camera.json"
    instrument.write_text('{"camera": {"resolution": 48}}')
    measurement = brdfkit.measure(sample, schedule="inplane:step=20", instrument=str(instrument),
                                  seed=2)
    measurement.save(str(tmp_path / "python.csv"))
    brdf("measure", "--sample", sample, "--schedule", "inplane:step=20", "--instrument",
         instrument, "--seed", 2, "--out", tmp_path / "cli.csv", "--quiet")
    assert (tmp_path / "python.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    assert measurement.metadata["instrument"] == str(instrument)
