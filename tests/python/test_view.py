"""brdfkit.view: the same page as `brdf view`, from strings or Model objects."""
import pytest

import brdfkit

SPEC = "ggx:rho_d=0.3,0.2,0.1:f0=0.9:alpha=0.2"


def test_view_equals_brdf_view(brdf, tmp_path):
    brdf("view", SPEC, "lambert:rho_d=0.5", "--out", tmp_path / "cli.html", "--quiet")
    cli = (tmp_path / "cli.html").read_text(encoding="utf-8")
    assert brdfkit.view([SPEC, "lambert:rho_d=0.5"]) == cli
    assert brdfkit.view([SPEC, brdfkit.model("lambert:rho_d=0.5")]) == cli
    assert brdfkit.view([SPEC, "lambert:rho_d=0.5"], out=str(tmp_path / "py.html")) is None
    assert (tmp_path / "py.html").read_text(encoding="utf-8") == cli


def test_view_refuses_what_is_not_a_source(tmp_path):
    with pytest.raises(brdfkit.UsageError):
        brdfkit.view([3])
    with pytest.raises(brdfkit.InputError):
        brdfkit.view([str(tmp_path / "absent.astm")])
