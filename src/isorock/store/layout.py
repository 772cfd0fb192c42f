"""Names of the store: layout version, table columns and their units (documented in :mod:`isorock.store`)."""

from __future__ import annotations

from ..constants import OUTCOME_LEGEND

__all__ = [
    "LAYOUT_VERSION",
    "OUTCOME_LEGEND",
    "OVERTURN_COLUMNS",
    "PULSE_COLUMNS",
    "MAP_INDEX_COLUMNS",
    "RECORD_SUMMARY_COLUMNS",
    "COLUMN_UNITS",
    "MAP_AXIS_UNITS",
]

LAYOUT_VERSION = 2

_CASE_COLUMNS = ("case", "isolation", "Tb_s", "xi_b", "rho", "mu_b", "R_b_m")
_BLOCK_COLUMNS = ("lambda_", "R_m", "b_m", "h_m", "tan_alpha")
_RESULT_COLUMNS = (
    "min_overturn_g", "overturns", "min_overturn_over_tan_alpha", "uplift_g", "uplift_over_tan_alpha",
    "n_analyses", "amp_max_g", "resolution", "stalls",
)  # fmt: skip
#: columns of ``/overturn/<id>`` and ``/summary/overturn``
OVERTURN_COLUMNS: tuple[str, ...] = (
    ("record",) + _BLOCK_COLUMNS + _CASE_COLUMNS + _RESULT_COLUMNS + ("record_pga_g", "scale_min")
)
#: columns of the ``/pulses/overturn_*`` tables
PULSE_COLUMNS: tuple[str, ...] = (
    ("pulse", "td_s", "omega_p_rad_s", "series", "param", "value")
    + _BLOCK_COLUMNS
    + _CASE_COLUMNS
    + _RESULT_COLUMNS
)
#: columns of ``/summary/maps``
MAP_INDEX_COLUMNS: tuple[str, ...] = (
    "path", "source", "source_kind", "map", "kind", "case", "isolation", "Tb_s", "xi_b", "rho", "mu_b",
    "R_b_m", "lambda_", "R_m", "pulse", "td_s", "amp_g", "amp_source", "nx", "ny", "no_uplift", "rocking",
    "overturn", "n_analyses", "seconds",
)  # fmt: skip

#: columns of ``/summary/records`` (the ``/records/<id>`` attributes, without the arrays)
RECORD_SUMMARY_COLUMNS: tuple[str, ...] = (
    "record", "label", "event", "year", "station", "component", "azimuth_deg", "component_method",
    "component_qa", "table1_component", "catalog_id", "source_file", "rotated_from", "source_format",
    "substitute", "npts",
    "dt_s", "duration_s", "pga_g", "pgv_m_s", "pgd_m", "arias_m_s", "d5_95_s", "Tp_s", "Tp_mp_s", "Tp_br_s",
    "tp_method", "Tp_method_s", "pulse_like", "pulse_indicator", "table1_pga_g", "table1_pgv_m_s",
    "table1_tp_s", "tp_source", "qa_passed", "record_sha256",
)  # fmt: skip
#: units of the axes of a regime map
MAP_AXIS_UNITS: dict[str, str] = {"lambda": "-", "R_m": "m", "Tb_s": "s", "xi_b": "-"}

#: units of the table columns (JSON attribute ``units`` of each table group)
COLUMN_UNITS: dict[str, str] = {
    "lambda_": "-", "R_m": "m", "b_m": "m", "h_m": "m", "tan_alpha": "-", "Tb_s": "s", "xi_b": "-",
    "rho": "-", "mu_b": "-", "R_b_m": "m", "min_overturn_g": "g", "min_overturn_over_tan_alpha": "-",
    "uplift_g": "g", "uplift_over_tan_alpha": "-", "amp_max_g": "g", "record_pga_g": "g",
    "scale_min": "-", "resolution": "-", "td_s": "s", "omega_p_rad_s": "rad/s", "value": "units of param",
    "eps": "-",
    "beta1_over_h": "-", "eps_housner": "-", "amp_g": "g", "seconds": "s", "pga_g": "g",
    "pgv_m_s": "m/s", "pgd_m": "m", "arias_m_s": "m/s", "d5_95_s": "s", "Tp_s": "s", "Tp_mp_s": "s",
    "Tp_br_s": "s", "Tp_method_s": "s", "azimuth_deg": "deg",
    "dt_s": "s", "duration_s": "s", "table1_pga_g": "g", "table1_pgv_m_s": "m/s", "table1_tp_s": "s",
}  # fmt: skip
