"""Bad input raises brdfkit's exceptions, naming the file and the line or byte, never a crash."""
import numpy as np
import pytest

import brdfkit


def test_missing_file_is_an_input_error_with_its_path(tmp_path):
    path = str(tmp_path / "absent.csv")
    with pytest.raises(brdfkit.InputError) as raised:
        brdfkit.read(path)
    assert raised.value.path == path
    assert path in str(raised.value)
    assert isinstance(raised.value, brdfkit.Error)


def test_broken_text_file_names_its_line(tmp_path):
    path = tmp_path / "broken.csv"
    path.write_text("# brdfkit measurement v1\n"
                    "theta_i,phi_i,theta_o,phi_o,r,g,b\n"
                    "10,0,20,180,0.1,0.1,0.1\n"
                    "10,0,20,180,0.1,zero,0.1\n")
    with pytest.raises(brdfkit.InputError) as raised:
        brdfkit.read(str(path))
    assert raised.value.path == str(path)
    assert raised.value.line == 4
    assert raised.value.byte is None


def test_truncated_binary_file_names_its_byte(data_dir, tmp_path):
    source = (data_dir / "rgl-bsdf" / "paper_white_rgb.bsdf").read_bytes()
    path = tmp_path / "truncated.bsdf"
    path.write_bytes(source[:len(source) // 2])
    with pytest.raises(brdfkit.InputError) as raised:
        brdfkit.read(str(path))
    assert raised.value.path == str(path)
    assert isinstance(raised.value.byte, int) and raised.value.byte >= 0
    assert raised.value.line is None


def test_fit_of_a_missing_path_names_it(tmp_path):
    path = str(tmp_path / "nothing.astm")
    with pytest.raises(brdfkit.InputError) as raised:
        brdfkit.fit(path, model="lambert")
    assert raised.value.path == path


def test_usage_errors_are_value_errors():
    with pytest.raises(brdfkit.UsageError, match="no-such-model"):
        brdfkit.model("no-such-model:rho_d=0.5")
    with pytest.raises(ValueError):
        brdfkit.model("lambert:rho_d=half")
    with pytest.raises(brdfkit.UsageError, match="loss"):
        brdfkit.fit(brdfkit.Measurement(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3))),
                    model="lambert", loss="cubic")
    with pytest.raises(brdfkit.UsageError, match="shape"):
        brdfkit.model("lambert").eval(np.zeros((4, 2)), np.zeros((4, 3)))
    with pytest.raises(brdfkit.UsageError, match="rows"):
        brdfkit.model("lambert").eval(np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(brdfkit.UsageError, match="threads"):
        brdfkit.energy("lambert", threads=-1)
    with pytest.raises(brdfkit.UsageError, match="source"):
        brdfkit.energy(42)


def test_bad_fit_report_is_an_input_error(tmp_path):
    path = tmp_path / "fit.json"
    path.write_text('{"model": "lambert"}')
    with pytest.raises(brdfkit.InputError) as raised:
        brdfkit.model(str(path))
    assert raised.value.path == str(path)


def test_unwritable_output_is_an_output_error(data_dir, tmp_path):
    measurement = brdfkit.read(str(data_dir / "cornell-astm" / "cayman.astm"))
    path = str(tmp_path / "no-such-directory" / "out.csv")
    with pytest.raises(brdfkit.OutputError) as raised:
        measurement.save(path)
    assert raised.value.path == path
