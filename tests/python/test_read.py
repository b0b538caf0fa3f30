"""brdfkit.read and Measurement: the reader's samples, without a copy, equal to the CLI's."""
import numpy as np
import pytest

import brdfkit
from conftest import cli_json


def test_read_equals_brdf_convert(brdf, data_dir, tmp_path):
    source = data_dir / "cornell-astm" / "cayman.astm"
    measurement = brdfkit.read(str(source))
    measurement.save(str(tmp_path / "python.csv"))
    brdf("convert", source, tmp_path / "cli.csv")
    assert (tmp_path / "python.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()

    info = cli_json(brdf("info", source, "--json"))
    assert len(measurement) == info["samples"]
    assert measurement.format == info["format"] == "astm"
    assert measurement.source == str(source)
    assert measurement.metadata["illuminant"].startswith("D65")
    assert not measurement.tabulated
    # NUM_POINTS 1439 in the file's header, read by hand.
    assert len(measurement) == 1439
    assert measurement.wi.shape == measurement.wo.shape == measurement.rgb.shape == (1439, 3)
    np.testing.assert_allclose(np.linalg.norm(measurement.wi, axis=1), 1.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(measurement.wo, axis=1), 1.0, rtol=0, atol=1e-12)


def test_native_csv_round_trip_is_exact(data_dir, tmp_path):
    measurement = brdfkit.read(str(data_dir / "cornell-astm" / "cayman.astm"))
    measurement.save(str(tmp_path / "copy.csv"))
    copy = brdfkit.read(str(tmp_path / "copy.csv"))
    np.testing.assert_array_equal(copy.rgb, measurement.rgb)


def test_sample_arrays_are_views_without_a_copy(data_dir):
    measurement = brdfkit.read(str(data_dir / "cornell-astm" / "cayman.astm"))
    wi, wo, rgb = measurement.wi, measurement.wo, measurement.rgb
    # One array of samples (wi, wo, value, missing per row): the three views step through the
    # same rows, 24 bytes apart inside a row, and each is owned by the Measurement.
    assert wi.strides[0] == wo.strides[0] == rgb.strides[0] > 3 * 3 * 8
    assert wi.strides[1] == 8
    assert wo.ctypes.data == wi.ctypes.data + 24
    assert rgb.ctypes.data == wi.ctypes.data + 48
    assert wi.base is measurement and rgb.base is measurement
    # A second access is the same memory, not a new copy.
    assert np.shares_memory(measurement.rgb, rgb)
    assert measurement.rgb.ctypes.data == rgb.ctypes.data
    assert not rgb.flags.writeable
    with pytest.raises(ValueError):
        rgb[0, 0] = 1.0


def test_sigma_is_a_view_of_its_own_array(brdf, tmp_path):
    brdf("measure", "--sample", "model:lambert:rho_d=0.5", "--schedule",
         "inplane:step=30", "--out", tmp_path / "lambert.csv", "--quiet")
    measurement = brdfkit.read(str(tmp_path / "lambert.csv"))
    sigma = measurement.sigma
    assert sigma.shape == (len(measurement), 3) and sigma.strides == (24, 8)
    assert sigma.base is measurement
    assert np.shares_memory(measurement.sigma, sigma)
    assert np.all(sigma > 0)


def test_tabulated_reader_evaluates_between_samples(data_dir):
    measurement = brdfkit.read(str(data_dir / "rgl-bsdf" / "paper_white_rgb.bsdf"))
    assert measurement.tabulated
    # At the reader's own sample directions, its evaluator gives back its samples.
    rows = np.flatnonzero(~measurement.missing)[::997][:50]
    values = measurement.eval(measurement.wi[rows], measurement.wo[rows])
    np.testing.assert_allclose(values, measurement.rgb[rows], rtol=1e-9, atol=0)
    # Reciprocity of a measured isotropic BRDF table, within the table's interpolation.
    assert values.shape == (len(rows), 3)


def test_eval_without_a_table_is_a_usage_error(data_dir):
    measurement = brdfkit.read(str(data_dir / "cornell-astm" / "cayman.astm"))
    with pytest.raises(brdfkit.UsageError, match="tabulated is False"):
        measurement.eval(measurement.wi, measurement.wo)


def test_measurement_from_arrays_fits_like_a_file(tmp_path):
    model = brdfkit.model("lambert:rho_d=0.25,0.5,0.75")
    rng = np.random.default_rng(5)
    wi = _hemisphere(rng, 400)
    wo = _hemisphere(rng, 400)
    measurement = brdfkit.Measurement(wi, wo, model.eval(wi, wo), metadata={"sample": "arrays"})
    assert measurement.metadata == {"sample": "arrays"}
    np.testing.assert_array_equal(measurement.wi, wi)
    fit = brdfkit.fit(measurement, model="lambert", threads=1)
    np.testing.assert_allclose(fit.params["rho_d"], [0.25, 0.5, 0.75], rtol=1e-6)


def _hemisphere(rng, count):
    directions = rng.normal(size=(count, 3))
    directions[:, 2] = np.abs(directions[:, 2]) + 0.05
    return directions / np.linalg.norm(directions, axis=1, keepdims=True)
