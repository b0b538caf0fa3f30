"""brdfkit.export and the energy verdicts: the CLI's reports, and its warnings as UserWarnings."""
import json
import warnings

import pytest

import brdfkit
from conftest import cli_json, without_times


def test_energy_verdicts_and_reasons_equal_the_cli(brdf, data_dir):
    cases = {
        "ggx:rho_d=0.2:f0=0.04:alpha=0.2": "conserving",
        "blinn-phong:rho_d=0:rho_s=8:m=100": "not conserving",
        str(data_dir / "rgl-bsdf" / "satin_rosaline_rgb.bsdf"): "undecided",
    }
    for source, verdict in cases.items():
        energy = brdfkit.energy(source, theta_steps=90)
        cli = cli_json(brdf("energy", source, "--json", "--quiet"))
        assert energy.verdict == cli["verdict"] == verdict, source
        assert energy.reason == cli["reason"] and energy.reason, source
    satin = brdfkit.energy(str(data_dir / "rgl-bsdf" / "satin_rosaline_rgb.bsdf"))
    assert "beyond the largest measured incidence (78.7 deg)" in satin.reason


def test_export_warns_when_the_renderer_loses_the_fit(data_dir, tmp_path):
    sunflower = brdfkit.read(str(data_dir / "rgl-bsdf" / "cg_sunflower_rgb.bsdf"))
    # l2 spends the lobe on the few samples of the sunflower's 1000 sr^-1 peak: a lobe narrower
    # than any renderer's target holds.
    blinn_phong = brdfkit.fit(sunflower, model="blinn-phong", loss="l2")
    with pytest.warns(UserWarning, match="differs from the fit by up to"):
        report = brdfkit.export(blinn_phong, to="gltf", samples=sunflower,
                                out=str(tmp_path / "bp.gltf"))
    assert report["warnings"] and report["error"]["max_relative"] > 10
    red, green, blue = report["mapped_from"]["rho_d"]
    assert red > 1.5 * green > 15 * blue  # the yellow kept
    assert json.loads((tmp_path / "bp.gltf").read_text())["materials"][0]
    ggx = brdfkit.fit(sunflower, model="ggx")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a healthy export must not warn
        healthy = brdfkit.export(ggx, to="gltf", samples=sunflower)
    assert healthy["warnings"] == [] and healthy["error"]["max_relative"] < 1


def test_export_report_equals_the_cli(brdf, tmp_path):
    fit = tmp_path / "fit.json"
    fit.write_text(json.dumps({"model": "ggx", "params": {
        "rho_d": [0.3, 0.2, 0.1], "f0": [0.04, 0.04, 0.04], "alpha": 0.2}}))
    for target in ("mitsuba3", "pbrt-v4", "gltf"):
        out = tmp_path / ("m." + target)
        report = brdfkit.export(str(fit), to=target, out=str(out))
        cli = json.loads(brdf("export", fit, "--to", target, "--out", out, "--json"))
        assert report.pop("text") == out.read_text()
        assert report == cli
