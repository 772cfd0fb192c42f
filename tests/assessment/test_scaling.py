"""The stripes' measure and component definition (isorock.assessment.scaling) and the scale of a run."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from isorock.assessment.hazard import HazardCurve
from isorock.assessment.hazard_files import curve_from_config
from isorock.assessment.scaling import Scaling, record_basis, scaling_from_config
from isorock.assessment.stripes import AssessedObject, run_levels
from isorock.errors import ConfigError, IsorockError
from isorock.physics.model import NoIsolation
from isorock.processing.imt import imt_value, parse_imt

from ..support.records import synthetic_record

HAZ = Path(__file__).resolve().parents[1] / "data" / "hazard"
USGS = {"usgs": str(HAZ / "dwight_7th.json"), "imt": "SA(1.0)"}


def _usgs() -> HazardCurve:
    return curve_from_config(USGS)


def test_a_measure_other_than_the_hazard_curves_is_refused_naming_both():
    with pytest.raises(ConfigError) as e:
        scaling_from_config({"imt": "PGA"}, _usgs())
    msg = str(e.value)
    assert (
        "\n" not in msg and "assessment.imt is PGA" in msg and "SA(1.0)" in msg and "dwight_7th.json" in msg
    )


def test_with_a_hazard_curve_the_records_are_scaled_on_its_component_definition():
    s = scaling_from_config({"imt": "sa(1)"}, _usgs())
    assert (s.imt, s.component, s.unit) == ("SA(1.0)", "RotD50", "g")
    assert "USGS" in s.basis and s.label == "SA(1.0) RotD50"


def test_the_analysed_component_with_a_rotd_curve_is_stated_as_an_assumption():
    s = scaling_from_config({"imt": "SA(1.0)", "component": "analysed"}, _usgs())
    assert s.component == "analysed" and "assumption" in s.basis and "RotD50" in s.basis


def test_another_definition_than_the_curves_is_refused():
    with pytest.raises(ConfigError, match="assessment.component is RotD100 but the hazard curve"):
        scaling_from_config({"imt": "SA(1.0)", "component": "RotD100"}, _usgs())


def test_without_a_hazard_curve_pga_of_the_analysed_component_unless_told():
    assert scaling_from_config({}) == Scaling("PGA", "analysed")
    assert scaling_from_config({"measure": "pga"}).imt == "PGA"  # the former key
    assert scaling_from_config({"imt": "PGV", "component": "rotd100"}).component == "RotD100"
    with pytest.raises(ConfigError, match="not an intensity measure"):
        scaling_from_config({"imt": "Sa 1 s"})


def test_the_basis_is_the_stored_rotd_value_or_the_analysed_components():
    gm = synthetic_record(3, 0.4)
    attrs = {"rotd50": json.dumps({"PGA": 0.31, "SA(1.0)": 0.52}), "rotd100": json.dumps({"PGA": 0.45})}
    assert record_basis("r", gm, attrs, Scaling("SA(1.0)", "RotD50")) == 0.52
    assert record_basis("r", gm, attrs, Scaling("PGA", "RotD100")) == 0.45
    assert record_basis("r", gm, attrs, Scaling("PGA", "analysed")) == pytest.approx(0.4)
    sa = record_basis("r", gm, {}, Scaling("SA(1.0)", "analysed"))
    assert sa == pytest.approx(imt_value(gm, parse_imt("SA(1.0)")))


def test_a_record_with_one_horizontal_is_refused_for_a_rotd_scaling_in_one_line():
    gm = synthetic_record(3, 0.4)
    with pytest.raises(IsorockError) as e:
        record_basis("IMV79-E05", gm, {"rotd50": "{}", "rotd100": "{}"}, Scaling("PGA", "RotD50"))
    msg = str(e.value)
    assert "\n" not in msg and "IMV79-E05" in msg and "assessment.component: analysed" in msg


def test_a_period_beyond_the_records_usable_band_is_refused():
    gm = synthetic_record(3, 0.4)
    attrs = {"rotd50": json.dumps({"SA(3.0)": 0.2}), "luf_hz": 0.5}
    with pytest.raises(IsorockError, match="beyond its usable band"):
        record_basis("RSN1", gm, attrs, Scaling("SA(3.0)", "RotD50"))
    with pytest.raises(IsorockError, match="outside the periods it supports"):
        record_basis("r", gm, {"rotd50": json.dumps({"SA(20.0)": 0.01})}, Scaling("SA(20.0)", "RotD50"))


def test_each_level_scales_the_analysed_component_by_level_over_basis():
    gm = synthetic_record(5, 0.3)
    o = AssessedObject("block", 4.0, 1.0, 0.8)
    runs = run_levels([o.system(NoIsolation())], gm, [0.2, 0.4], 0.8, slide_allow_m=None, basis=0.25)
    assert np.allclose(runs["scale"], [0.8, 1.6])
    assert np.allclose(runs["level"], [0.2, 0.4])
    assert np.allclose(runs["pga_g"], [0.8 * 0.3, 1.6 * 0.3])
