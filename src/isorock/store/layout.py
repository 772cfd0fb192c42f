"""Names of the store: layout version, table columns and their units, the attributes of a record
(:data:`RECORD_ATTRS`, the one spec the job writers, the merge and the documentation use) and the
contents of ``/pulses/restitution`` (:func:`restitution_table`); documented in :mod:`isorock.store`."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import pandas as pd

from isorock.constants import OUTCOME_LEGEND
from isorock.physics.model import housner_restitution, impact_coefficients

__all__ = [
    "LAYOUT_VERSION",
    "LAYOUT_HISTORY",
    "OUTCOME_LEGEND",
    "OVERTURN_COLUMNS",
    "PULSE_COLUMNS",
    "MAP_INDEX_COLUMNS",
    "RECORD_SUMMARY_COLUMNS",
    "COLUMN_UNITS",
    "MAP_AXIS_UNITS",
    "MAP_AXIS_LONG_NAMES",
    "RecordAttr",
    "RECORD_ATTRS",
    "record_attr_names",
    "record_attrs_in_order",
    "describe_record_attrs",
    "RESTITUTION_RHOS",
    "restitution_table",
]

#: version of the layout written (root attribute ``layout_version``); :data:`LAYOUT_HISTORY` says what
#: each version changed and :mod:`isorock.store.reader` reads the older ones
LAYOUT_VERSION = 7

#: what each layout version changed
LAYOUT_HISTORY: dict[int, str] = {
    2: "records, maps, pulse, summary and assessment tables (the layout of isorock 0.1)",
    3: "/records/<id> attribute processing_json: the processing steps as JSON objects (step, parameters, "
    "note); the lines of /records/<id>/processing are kept for people",
    4: "the vertical (issue 24): /records/<id> attributes vertical_component, vertical_pga_g, "
    "vertical_pgv_m_s, vertical_note (last columns of /summary/records) and the dataset vertical; "
    "/overturn/<id> columns with_vertical, min_overturn_h_g, min_overturn_hv_g; the assessment's sliding "
    "columns (mode, sliding_peak_m, sliding_residual_m, n_slips, slide_allow_m, slides_beyond)",
    5: "HDF5 dimension scales (netCDF-4: xarray with h5netcdf reads named dimensions and coordinates): the "
    "axes of a map (lambda_ and R_m, or Tb_s and xi_b; attribute long_name) are the coordinates of codes "
    "and max_theta_over_alpha; /records/<id>/time_s [s] (k dt) of acc and vertical, "
    "/records/<id>/pulse/time_s of the pulse velocities; the dimension line (no values) of "
    "/records/<id>/processing; beside each pandas table the dimension row (no values, the table's length: "
    "HDF5 attaches no scale to a PyTables table, h5netcdf gives the table the dimension of its length). "
    "Datasets added, none changed: isorock reads a store of layout 2 to 4 as before",
    6: "adequacy (issue 31): /assessment/runs holds every candidate's runs, the design search's fixed base "
    "and grid isolators as case design/<candidate>, with the columns candidate, source, isolation, Tb_s, "
    "xi_b, mu_b, R_b_m, rho; exceeds_capacity and failure count gamma_x times the displacement; "
    "/assessment/design adds target_estimate, adequate, p_failure_mce and the familywise "
    "vs_floor_p_adjusted; "
    "/assessment/verdicts adds target (JSON), closest, decided_by, n_family, equivalence_margin, gamma_x; "
    "/assessment/design_levels adds p_failure_mce and the displacement checks times gamma_x; "
    "/assessment/hazard adds annual_rate_exact_ci95 and deaggregation (JSON); the verdict restrain",
    7: "the intensity measure (issue 33): /records/<id> attributes rotd_pair, rotd50, rotd100 (JSON "
    "{measure: value}; last columns of /summary/records); the assessment's runs name their level column "
    "level (in assessment.imt of its component definition: /assessment attributes imt, component, unit "
    "and the table /assessment/measure, with the hazard curve's measure, definition and source) and keep "
    "pga_g, the analysed component's PGA at that level; the recording's metadata (records add "
    "--peer-search): /records/<id> attributes rsn, mw, mechanism, rjb_km, rrup_km, vs30_m_s, luf_hz "
    "(mw, rjb_km, vs30_m_s, luf_hz: last columns of /summary/records, NaN when not known)",
}

_CASE_COLUMNS = ("case", "isolation", "Tb_s", "xi_b", "rho", "mu_b", "R_b_m")
_BLOCK_COLUMNS = ("lambda_", "R_m", "b_m", "h_m", "tan_alpha")
_RESULT_COLUMNS = (
    "min_overturn_g", "overturns", "min_overturn_over_tan_alpha", "uplift_g", "uplift_over_tan_alpha",
    "n_analyses", "amp_max_g", "resolution", "stalls",
)  # fmt: skip
#: columns of ``/overturn/<id>`` and ``/summary/overturn``
OVERTURN_COLUMNS: tuple[str, ...] = (
    ("record",)
    + _BLOCK_COLUMNS
    + _CASE_COLUMNS
    + _RESULT_COLUMNS
    + ("record_pga_g", "scale_min", "with_vertical", "min_overturn_h_g", "min_overturn_hv_g")
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


AttrKind = Literal["text", "json", "number", "integer", "flag"]


@dataclass(frozen=True)
class RecordAttr:
    """One attribute of a ``/records/<id>`` group.

    Attributes
    ----------
    name : str
        Attribute name.
    unit : str
        Unit of a number (``s``, ``g``, ``m/s``, ``deg``; ``-`` dimensionless); "" for text, JSON,
        integers that are counts or years, and flags.
    description : str
        What it holds.
    kind : {"text", "json", "number", "integer", "flag"}
        How it is stored: str, JSON text, float (NaN if unknown), int, 0/1 (int8).
    job : {"process_record", "extract_pulse"}
        The workflow job that writes it (:mod:`isorock.jobs.record`); the merge copies the
        ``extract_pulse`` ones from ``/records/<id>/pulse``.
    summary : bool
        Also a column of ``/summary/records`` (in the order of :data:`RECORD_ATTRS`).
    """

    name: str
    unit: str
    description: str
    kind: AttrKind = "number"
    job: str = "process_record"
    summary: bool = False


def _a(
    name: str, unit: str, description: str, kind: AttrKind = "number", *, summary: bool = False
) -> RecordAttr:
    """An attribute written by ``process_record``."""
    return RecordAttr(name, unit, description, kind, "process_record", summary)


def _p(name: str, unit: str, description: str, kind: AttrKind = "number") -> RecordAttr:
    """An attribute written by ``extract_pulse`` (a column of ``/summary/records``)."""
    return RecordAttr(name, unit, description, kind, "extract_pulse", True)


#: the attributes of ``/records/<id>``: the one spec of the job writers, the merge and the documentation
#: (``/summary/records`` has the ones marked ``summary``, in this order, after its column ``record``)
RECORD_ATTRS: tuple[RecordAttr, ...] = (
    _a("id", "", "record id", "text"),
    _a("label", "", "label (event, station)", "text", summary=True),
    _a("event", "", "earthquake", "text", summary=True),
    _a("year", "", "year of the event (-1 if unknown)", "integer", summary=True),
    _a("station", "", "recording station", "text", summary=True),
    _a(
        "component",
        "",
        "direction analysed: SN/SP when it is the row's, else the recorded component's name",
        "text",
        summary=True,
    ),
    _a("azimuth_deg", "deg", "azimuth of the component analysed (NaN if not known)", summary=True),
    _a(
        "component_method",
        "",
        'how it was obtained: "provided" | "rotated" | "aligned" | "as recorded"',
        "text",
        summary=True,
    ),
    _a("component_description", "", "how it was obtained, in words", "text"),
    _a(
        "component_qa",
        "",
        'a QA mark when the direction is not the row\'s, "" otherwise',
        "text",
        summary=True,
    ),
    _a(
        "table1_component",
        "",
        'the Table 1 row\'s component (SN, SP, 090 ...; "" if not a row)',
        "text",
        summary=True,
    ),
    _a("target_azimuth_deg", "deg", "azimuth of the row's direction (NaN if none)"),
    _a("strike_deg", "deg", "fault strike of the row (NaN if none)"),
    _a("strike_source", "", "where the strike comes from", "text"),
    _a("catalog_id", "", 'Table 1 id ("" if none)', "text", summary=True),
    _a("record_source", "", "where the records came from", "text"),
    _a("source_file", "", "the file read (the first file of a rotation)", "text", summary=True),
    _a(
        "rotated_from",
        "",
        "file, sha256, component, azimuth_deg of both inputs of a rotation ([] if not rotated)",
        "json",
        summary=True,
    ),
    _a("source_format", "", "format the file was read as", "text", summary=True),
    _a("file_units", "", "units of the values in the file", "text"),
    _a("file_units_source", "", '"header" | "given"', "text"),
    _a("file_component", "", "the recorded component read", "text"),
    _a("candidates", "", "every direction considered, the one chosen", "json"),
    _a("substitute", "", "a substitute for the row's record (0/1)", "flag", summary=True),
    _a("npts", "", "samples of the processed record", "integer", summary=True),
    _a("dt_s", "s", "time step", summary=True),
    _a("duration_s", "s", "duration", summary=True),
    _a("pga_g", "g", "peak ground acceleration", summary=True),
    _a("pga_m_s2", "m/s^2", "peak ground acceleration"),
    _a("pgv_m_s", "m/s", "peak ground velocity", summary=True),
    _a("pgd_m", "m", "peak ground displacement", summary=True),
    _a("arias_m_s", "m/s", "Arias intensity", summary=True),
    _a("d5_95_s", "s", "significant duration D5-95", summary=True),
    _a("final_disp_m", "m", "displacement at the end of the processed record"),
    _p("Tp_s", "s", "pulse period, db4 wavelet (Baker 2007)"),
    _p("Tp_mp_s", "s", "pulse period, Mavroeidis-Papageorgiou fit (NaN if not fitted)"),
    _p("Tp_br_s", "s", "pulse period, Bray & Rodriguez-Marek"),
    _p("tp_method", "", 'definition of the catalog\'s Tp: "mp" | "br" | "wavelet"', "text"),
    _p("Tp_method_s", "s", "pulse period by tp_method"),
    _p("pulse_like", "", "pulse-like record (0/1)", "flag"),
    _p("pulse_indicator", "-", "pulse indicator (Baker 2007)"),
    _a("table1_pga_g", "g", "Table 1 PGA (NaN if not a catalog row)", summary=True),
    _a("table1_pgv_m_s", "m/s", "Table 1 PGV (NaN if not a catalog row)", summary=True),
    _a("table1_tp_s", "s", "Table 1 Tp (NaN if not a catalog row)", summary=True),
    _a("tp_source", "", "published source of the Table 1 Tp", "text", summary=True),
    _a("table1_check", "", 'PGA/PGV more than 1.5 x off Table 1\'s, or ""', "text"),
    _a("qa_passed", "", "no QA check failed the record (0/1)", "flag", summary=True),
    _a("qa_reasons", "", "why QA checks failed it", "json"),
    _a("record_sha256", "", "sha256 of the file read", "text", summary=True),
    _a(
        "processing_json",
        "",
        "processing steps in order, each {step, parameters, note} (layout 3; isorock.processing.AppliedStep)",
        "json",
    ),
    _a("config_hash", "", "sha256 of the job's parameters", "text"),
    _a("isorock_version", "", "isorock version of the job", "text"),
    _a("units", "", "units of acc, dt_s, pga_g, pgv_m_s, pgd_m, azimuth_deg", "json"),
    # layout 4: the vertical beside the component analysed (issue 24), after the columns of layout 2
    _a(
        "vertical_component",
        "",
        'the vertical found beside the component analysed, "file:component" ("" if none: see vertical_note)',
        "text",
        summary=True,
    ),
    _a("vertical_pga_g", "g", "peak vertical acceleration, processed alike (NaN if none)", summary=True),
    _a("vertical_pgv_m_s", "m/s", "peak vertical velocity, processed alike (NaN if none)", summary=True),
    _a("vertical_note", "", "how the vertical was found and checked, or why none was", "text", summary=True),
    # layout 7: the RotD50 and RotD100 of the two horizontals (issue 33)
    _a(
        "rotd_pair",
        "",
        'the two processed horizontals of the recording the RotD values are of ("" if it has one only)',
        "text",
        summary=True,
    ),
    _a(
        "rotd50",
        "",
        "RotD50 of the two horizontals, {measure: value} (PGA, SA in g, PGV in cm/s; {} if one horizontal)",
        "json",
        summary=True,
    ),
    _a("rotd100", "", "RotD100 of the two horizontals, {measure: value} (as rotd50)", "json", summary=True),
    # layout 7: the recording's metadata (records add --peer-search: PEER's _SearchResults.csv)
    _a("rsn", "", "PEER record sequence number (-1 if none)", "integer"),
    _a("mw", "-", "moment magnitude of the earthquake (NaN if not known)", summary=True),
    _a("mechanism", "", 'fault mechanism ("" if not known)', "text"),
    _a("rjb_km", "km", "Joyner-Boore distance (NaN if not known)", summary=True),
    _a("rrup_km", "km", "rupture distance (NaN if not known)"),
    _a("vs30_m_s", "m/s", "Vs30 of the station (NaN if not known)", summary=True),
    _a(
        "luf_hz",
        "Hz",
        "lowest usable frequency (NaN if not known): the high-pass corner is raised to it; a spectral "
        "measure at a period longer than 1/luf_hz is not supported by the record",
        summary=True,
    ),
)

#: columns of ``/summary/records``: ``record`` (the id), then the :data:`RECORD_ATTRS` marked ``summary``
RECORD_SUMMARY_COLUMNS: tuple[str, ...] = ("record",) + tuple(a.name for a in RECORD_ATTRS if a.summary)


def record_attr_names(job: str | None = None) -> tuple[str, ...]:
    """Names of the :data:`RECORD_ATTRS` (of one job's when ``job`` is given), in order."""
    return tuple(a.name for a in RECORD_ATTRS if job is None or a.job == job)


def record_attrs_in_order(values: Mapping[str, Any], job: str) -> dict[str, Any]:
    """The attributes a job writes on ``/records/<id>``: ``values`` in the order of the spec.

    Parameters
    ----------
    values : mapping
        Attribute name to value.
    job : {"process_record", "extract_pulse"}
        The job.

    Raises
    ------
    ValueError
        ``values`` is not exactly the job's attributes of :data:`RECORD_ATTRS`.
    """
    names = record_attr_names(job)
    missing = [k for k in names if k not in values]
    extra = [k for k in values if k not in names]
    if missing or extra:
        raise ValueError(
            f"{job}: record attributes differ from RECORD_ATTRS: missing {missing}, extra {extra}"
        )
    return {k: values[k] for k in names}


def describe_record_attrs(attrs: Iterable[RecordAttr] = RECORD_ATTRS) -> str:
    """The spec as text, one line per attribute: ``name [unit] (kind, job): description``."""
    lines = []
    for a in attrs:
        unit = f" [{a.unit}]" if a.unit else ""
        lines.append(f"{a.name}{unit} ({a.kind}, {a.job}{', summary' if a.summary else ''}): {a.description}")
    return "\n".join(lines)


#: units of the axes of a regime map
MAP_AXIS_UNITS: dict[str, str] = {"lambda": "-", "R_m": "m", "Tb_s": "s", "xi_b": "-"}
#: what the axes of a regime map are (attribute ``long_name`` of their datasets, layout 5)
MAP_AXIS_LONG_NAMES: dict[str, str] = {
    "lambda": "slenderness h/b",
    "R_m": "block size R (half-diagonal)",
    "Tb_s": "isolation period Tb",
    "xi_b": "isolator damping ratio",
}

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
    "min_overturn_h_g": "g", "min_overturn_hv_g": "g", "vertical_pga_g": "g", "vertical_pgv_m_s": "m/s",
    "sliding_peak_m": "m", "sliding_residual_m": "m", "slide_allow_m": "m",
    "mw": "-", "rjb_km": "km", "vs30_m_s": "m/s", "luf_hz": "Hz",
}  # fmt: skip


#: mass ratios ``m/m_b`` [-] of ``/pulses/restitution``
RESTITUTION_RHOS: tuple[float, ...] = (0.1, 0.25, 0.5, 1.0, 2.0)


def restitution_table(
    rhos: Sequence[float] = RESTITUTION_RHOS, lambdas: Sequence[float] | None = None
) -> pd.DataFrame:
    """Impact coefficients against slenderness for several mass ratios (paper Eqs. 29-30, Fig 3).

    The table ``/pulses/restitution`` of the store, and what Fig 3 draws when a store has none.

    Parameters
    ----------
    rhos : sequence of float
        Block-to-base mass ratios ``m/m_b`` [-].
    lambdas : sequence of float, optional
        Slenderness values ``h/b`` [-] (default: 91 values from 1 to 10).

    Returns
    -------
    pandas.DataFrame
        Columns ``lambda_``, ``rho``, ``eps`` (angular restitution), ``beta1_over_h`` (``beta1 / h``),
        ``eps_housner`` (Housner's, rigid base), all [-]; one row per (rho, lambda).
    """
    lams = np.linspace(1.0, 10.0, 91) if lambdas is None else lambdas
    rows = []
    for rho in rhos:
        for lam in lams:
            h = 1.0
            eps, beta1, _ = impact_coefficients(float(lam), h, float(rho))
            rows.append(
                {
                    "lambda_": float(lam),
                    "rho": float(rho),
                    "eps": eps,
                    "beta1_over_h": beta1 / h,
                    "eps_housner": housner_restitution(math.atan(1.0 / float(lam))),
                }
            )
    return pd.DataFrame(rows)
