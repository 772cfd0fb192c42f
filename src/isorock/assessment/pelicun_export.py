"""The fitted fragilities of an assessment as a damage model of pelicun (``isorock assess
--export-fragility FILE.csv``).

pelicun (NHERI SimCenter, https://github.com/NHERI-SimCenter/pelicun) reads a damage model from a CSV
file of one row per component, the columns named ``<group>-<item>``, and turns the column names into a
two-level index by splitting them at ``-`` (``pelicun/file_io.py`` ``load_data``, which calls
``pelicun/base.py`` ``convert_to_MultiIndex``; the first column, the component ID, is split the same
way). The columns written here are those of pelicun's own test model
(``pelicun/tests/basic/data/model/test_DamageModel/load_model_parameters/damage_db.csv``) and of the
Hazus databases pelicun loads (``simcenter-dlml``, ``seismic/transportation_network/portfolio/Hazus
v5.1/fragility.csv``):

``ID``
    ``<object>.<case>.<damage>``, e.g. ``statue.lin3.failure``: the object and the isolation case of the
    configuration and the failure mode fitted (``overturn``; ``failure``: overturn, or the isolator
    beyond its displacement capacity, or an object that slides beyond its allowance; any other failure
    mode the fragility table holds, uplift excepted). Every character other than a letter, a digit,
    ``_`` and ``.`` becomes ``_``: pelicun splits an ID at ``-`` into index levels (``load_data`` with
    ``reindex=False``), and ``-`` separates the levels of its damage sample's columns
    (``cmp-loc-dir-uid``).
``Incomplete``
    0 (a row with 1 is dropped: ``DamageModel.remove_incomplete_components``).
``Demand-Type``
    ``Peak Ground Acceleration`` (PGA), ``Peak Ground Velocity`` (PGV) or ``Peak Spectral
    Acceleration|T`` (SA(T), the period in s after ``|`` as OpenQuake writes it: ``SA(1.0)`` ->
    ``Peak Spectral Acceleration|1.0``): the keys of ``pelicun/base.py`` ``EDP_to_demand_type``
    (``'Peak Ground Acceleration': 'PGA'``, ``'Peak Ground Velocity': 'PGV'``, ``'Peak Spectral
    Acceleration': 'SA'``; ``Spectral Acceleration`` is a synonym, which the Hazus bridges use). A
    subtype after ``|`` is appended to the demand: pelicun then asks its demand sample for the column
    ``SA_1.0-0-1`` (``pelicun/model/demand_model.py`` ``_get_required_demand_type``), as in pelicun's
    example ``collapse,0,Peak Spectral Acceleration|1.00,g,...`` (``pelicun/examples/0_tmp/
    fragility_Additional.csv``), whose sample holds ``SA_1.00-0-1``. The demand sample must name the
    period exactly as the ID's demand does.
``Demand-Unit``
    ``g`` for PGA and SA, ``cmps`` (cm/s) for PGV: pelicun's unit names
    (``pelicun/settings/default_units.json``: ``"g": 9.80665`` under acceleration, ``"cmps": 0.01``
    under velocity; the Hazus water pipelines give PGV in ``cmps``). The median is in the unit of the
    assessment's measure (:attr:`isorock.processing.imt.IMT.unit`: g, or cm/s for PGV).
``Demand-Offset``
    0: the measure is of the ground motion, location 0 of pelicun's demand sample (``PGA-0-1``); place
    the component at location 0 (pelicun's default ``DemandOffset`` shifts only PFA and PFV).
``Demand-Directional``
    1. pelicun then reads the demand of the component's own direction (``PGA-0-1``). With 0 it would take
    the largest of the directions of its sample times ``NonDirectionalMultipliers`` (1.2 by default,
    ``pelicun/settings/default_config.json``; ``pelicun/model/demand_model.py``
    ``_assemble_required_demand_data``): but the fragility is fitted to the measure as its component
    definition defines it, RotD50 or RotD100 (already independent of the orientation: no factor may be
    applied to it), or the one horizontal component analysed, along which the object rocks (a
    directional demand). Give pelicun the measure in that definition, in the direction of the
    component.
``LS1-Family``, ``LS1-Theta_0``, ``LS1-Theta_1``
    ``lognormal``, the median ``theta`` (in ``Demand-Unit``) and the logarithmic standard deviation
    ``beta`` [-] of the maximum-likelihood fit (:mod:`isorock.assessment.fragility`): one limit state,
    whose one damage state DS1 is the failure mode. The failure modes are separate components, not the
    limit states of one: pelicun's limit states of one component are nested and ordered, and two
    lognormal fits with their own beta may cross.
``LS1-DamageStateWeights``
    Empty (one damage state). The column must be there: pelicun reads ``cmp_data[ls,
    'DamageStateWeights']`` of every limit state when it counts the damage states
    (``pelicun/model/damage_model.py`` ``DSModel.complete_ds_cols``).
``Comment``
    What the row is: isorock's version, the object, base and failure mode, the measure and its
    component definition (RotD50, RotD100, analysed), the data of the fit (runs, stripes, damaged),
    the bootstrap intervals of the median and of beta, and the store it was read from. pelicun keeps a
    column it does not use (``ID`` and ``Comment`` have no ``-``: one level, ``('Comment', '')``) and
    reads no value from it (its loader looks up ``Incomplete``, ``Demand``, ``LS<i>`` only); its own
    databases keep descriptions in a JSON file beside the CSV instead.

A fit that is not estimable (no run damaged, every run damaged, stripes that separate the outcomes,
beta or median out of range: :func:`isorock.assessment.fragility.fit_fragility`) is left out, with the
reason (:class:`LeftOut`). The fragilities against the other measures of the runs
(``/assessment/fragility_by_measure``: PGV, Sa at each base's own isolation period) are not exported:
they describe the efficiency of each measure, not the assessment.

The measure is the attribute ``imt`` of the store's group ``/assessment`` (``PGA``, ``PGV``,
``SA(1.0)``; absent in a store of an earlier version: ``PGA``), its component definition the attribute
``component`` (absent: ``analysed``, the component the engine analyses).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import pandas as pd

from isorock.errors import IsorockError, ParameterError
from isorock.processing.imt import IMT, component_definition, parse_imt
from isorock.version import __version__

__all__ = [
    "PELICUN_COLUMNS",
    "DEMAND_TYPES",
    "PELICUN_UNITS",
    "LeftOut",
    "demand_type",
    "pelicun_unit",
    "component_id",
    "read_measure",
    "fragility_rows",
    "check_export_path",
    "write_pelicun_csv",
]

#: the columns written, in order (see the module's docstring)
PELICUN_COLUMNS: tuple[str, ...] = (
    "ID",
    "Incomplete",
    "Demand-Type",
    "Demand-Unit",
    "Demand-Offset",
    "Demand-Directional",
    "LS1-Family",
    "LS1-Theta_0",
    "LS1-Theta_1",
    "LS1-DamageStateWeights",
    "Comment",
)
#: pelicun's demand type of each measure (keys of ``pelicun/base.py`` ``EDP_to_demand_type``)
DEMAND_TYPES: dict[str, str] = {
    "PGA": "Peak Ground Acceleration",
    "PGV": "Peak Ground Velocity",
    "SA": "Peak Spectral Acceleration",
}
#: pelicun's name of each unit of :attr:`IMT.unit` (``pelicun/settings/default_units.json``)
PELICUN_UNITS: dict[str, str] = {"g": "g", "cm/s": "cmps"}
#: the damage states of the fragility table that are not failure modes (not exported by default)
NOT_FAILURE = ("uplift",)
#: the order of the failure modes in the file (any other after them, by name)
_ORDER = ("overturn", "exceed_capacity", "exceeds_capacity", "beyond_capacity", "failure")
_WORDS = {
    "overturn": "overturning",
    "failure": "failure (overturn, isolator beyond its capacity, or sliding beyond the allowance)",
    "exceed_capacity": "isolator displacement beyond its capacity",
    "exceeds_capacity": "isolator displacement beyond its capacity",
    "beyond_capacity": "isolator displacement beyond its capacity",
}


@dataclass(frozen=True)
class LeftOut:
    """A fit left out of the export, and why.

    Attributes
    ----------
    id : str
        The ID its row would have had.
    object, case, damage : str
        The object, the isolation case and the failure mode.
    reason : str
        Why (the fit's note: "not estimable: no damage in 30 runs up to 0.8").
    """

    id: str
    object: str
    case: str
    damage: str
    reason: str

    def line(self) -> str:
        """One line for the user: "left out statue.none.overturn: not estimable: no damage ..."."""
        return f"left out {self.id}: {self.reason}"

    def to_dict(self) -> dict[str, str]:
        """JSON-ready: ``id``, ``object``, ``case``, ``damage``, ``reason``."""
        return asdict(self)


def demand_type(imt: IMT) -> str:
    """pelicun's ``Demand-Type`` of a measure: ``Peak Ground Acceleration``, ``Peak Ground Velocity``,
    ``Peak Spectral Acceleration|1.0`` (the period [s] as :class:`IMT` writes it)."""
    base = DEMAND_TYPES[imt.name]
    return f"{base}|{float(imt.period_s)!r}" if imt.name == "SA" and imt.period_s is not None else base


def pelicun_unit(imt: IMT) -> str:
    """pelicun's ``Demand-Unit`` of a measure: ``g`` (PGA, SA) or ``cmps`` (PGV [cm/s])."""
    return PELICUN_UNITS[imt.unit]


def component_id(obj: str, case: str, damage: str) -> str:
    """The ID of a fit, ``<object>.<case>.<damage>``, each part with every character other than a
    letter, a digit, ``_`` and ``.`` replaced by ``_`` (pelicun splits an ID at ``-``)."""
    clean = [re.sub(r"[^A-Za-z0-9_.]", "_", str(p)) or "_" for p in (obj, case, damage)]
    return ".".join(clean)


def read_measure(store_path: str | os.PathLike) -> tuple[IMT, str]:
    """The intensity measure of a store's assessment and its component definition.

    Parameters
    ----------
    store_path : path-like
        The store (``results/isorock.h5``).

    Returns
    -------
    (IMT, str)
        The ``imt`` of ``/assessment/measure`` parsed (a store without it, layout 6 or older: PGA) and its
        ``component`` (absent: ``analysed``).

    Raises
    ------
    IsorockError
        Its ``unit``, where there, is not the measure's (:attr:`IMT.unit`).
    """
    from isorock.store import Store

    m = Store(store_path).table("assessment/measure")
    at = {} if m is None or not len(m) else m.iloc[0].to_dict()
    imt = parse_imt(at.get("imt") or "PGA", where=f"{store_path}: /assessment/measure imt")
    unit = at.get("unit")
    if unit and str(unit) != imt.unit:
        raise IsorockError(f"{store_path}: /assessment/measure states {imt} in {unit}, not in {imt.unit}")
    comp = at.get("component")
    return imt, (component_definition(comp, where="/assessment/measure component") if comp else "analysed")


def _fragility_table(source: Any) -> tuple[pd.DataFrame, str, IMT | None, str | None]:
    """The fragility table of ``source`` (a store's path, a :class:`~isorock.store.Store`, a mapping of
    tables, or the table), where it comes from, and the measure and component the store states."""
    from isorock.store import Store

    if isinstance(source, pd.DataFrame):
        return source, "tables", None, None
    if isinstance(source, Mapping):
        if "fragility" not in source:
            raise ParameterError("fragility_rows: the tables hold no 'fragility' table")
        m = source.get("measure")  # the stripes' measure (assessment_tables' "measure" row), if there
        if m is not None and len(m) and "imt" in m.columns:
            r = m.iloc[0]
            comp = str(r["component"]) if "component" in m.columns and str(r["component"]) else None
            return source["fragility"], "tables", parse_imt(r["imt"], where="measure imt"), comp
        return source["fragility"], "tables", None, None
    store = source if isinstance(source, Store) else Store(source)
    table = store.table("assessment/fragility")
    if table is None:
        raise IsorockError(f"{store.path}: no /assessment/fragility table: not an assessment's store")
    imt, comp = read_measure(store.path)
    return table, str(store.path), imt, comp


def _context(source: Any) -> dict[str, Any]:
    """What a store's configuration says about its fits, for the comments: each case's base in words,
    the capacity [m] and gamma_x behind "failure", and the highest stripe (empty for tables given
    without their store)."""
    import json

    from isorock.store import Store

    if isinstance(source, pd.DataFrame | Mapping):
        return {}
    store = source if isinstance(source, Store) else Store(source)
    try:
        cfg = json.loads(str(store.root_attrs.get("config_json", "{}")) or "{}")
    except ValueError:
        return {}
    a = cfg.get("assessment") or {}
    bases = {}
    for c in (cfg.get("isolation") or {}).get("cases") or []:
        kind = c.get("kind")
        bases[str(c.get("name"))] = (
            "fixed base"
            if kind == "none"
            else f"linear isolator Tb {c.get('Tb_s')} s, xi {c.get('xi_b')}"
            if kind == "linear"
            else f"friction pendulum mu {c.get('mu_b')}, R {c.get('R_b_m')} m"
            if kind == "fp"
            else str(kind)
        )
    stripes = [float(x) for x in a.get("stripes_g") or []]
    return {
        "bases": bases,
        "capacity_m": a.get("capacity_m"),
        "gamma_x": a.get("gamma_x", 1.2),
        "top": max(stripes) if stripes else None,
    }


def _float(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def _interval(row: Mapping[str, Any], name: str) -> str:
    lo, hi = _float(row.get(f"{name}_lo")), _float(row.get(f"{name}_hi"))
    return f"{lo:.3g} to {hi:.3g}" if math.isfinite(lo) and math.isfinite(hi) else "none"


def fragility_rows(
    source: str | os.PathLike | Mapping[str, pd.DataFrame] | pd.DataFrame | Any,
    *,
    imt: IMT | str | None = None,
    component: str | None = None,
    damages: Sequence[str] | None = None,
) -> tuple[pd.DataFrame, list[LeftOut]]:
    """The fitted fragilities of an assessment as the rows of a pelicun damage model.

    Parameters
    ----------
    source : path-like, Store, mapping or pandas.DataFrame
        A store (its ``/assessment/fragility`` table and the attributes ``imt`` and ``component`` of
        ``/assessment``), or the tables of :func:`isorock.jobs.assessment.assessment_tables`
        (their ``fragility``, and the measure of their ``measure`` where there), or that table itself:
        one row per object, case and damage state with
        ``object``, ``case``, ``damage``, ``median_g`` (or ``median``; in the measure's unit),
        ``beta`` [-], ``estimable`` (0/1), ``note`` and, where there, ``isolation``, ``n_runs``,
        ``n_levels``, ``n_damaged``, ``median_ci95_g_lo``/``_hi``, ``beta_ci95_lo``/``_hi``.
    imt : IMT or str, optional
        The measure the fragilities are fitted against (default: the store's, else PGA).
    component : str, optional
        Its component definition, RotD50, RotD100 or analysed (default: the store's, else analysed).
    damages : sequence of str, optional
        The damage states exported (default: every one of the table but uplift, which is not a
        failure).

    Returns
    -------
    (pandas.DataFrame, list of LeftOut)
        The rows (columns :data:`PELICUN_COLUMNS`; medians in the unit of ``Demand-Unit``), one per
        estimable fit, ordered by object, case and failure mode (overturn, then failure); and the
        fits left out, each with its reason.

    Raises
    ------
    IsorockError
        A store without the fragility table; two fits whose IDs coincide once cleaned.
    ParameterError
        A measure or component definition isorock does not know.
    """
    table, where, s_imt, s_comp = _fragility_table(source)
    ctx = _context(source)
    m = parse_imt(imt) if isinstance(imt, str) else (imt or s_imt or IMT("PGA"))
    comp = component_definition(component) if component else (s_comp or "analysed")
    median_col = "median" if "median" in table.columns else "median_g"
    rank = {d: i for i, d in enumerate(_ORDER)}
    wanted = None if damages is None else set(damages)
    recs = [
        r
        for r in table.to_dict("records")
        if (str(r["damage"]) in wanted if wanted is not None else str(r["damage"]) not in NOT_FAILURE)
    ]
    order: dict[str, int] = {}  # objects and cases in the order of the table
    for r in recs:
        order.setdefault(str(r["object"]), len(order))
    cases: dict[str, int] = {}
    for r in recs:
        cases.setdefault(str(r["case"]), len(cases))
    recs.sort(
        key=lambda r: (
            order[str(r["object"])], cases[str(r["case"])], rank.get(str(r["damage"]), len(_ORDER)),
            str(r["damage"]),
        )
    )  # fmt: skip
    rows: list[dict[str, Any]] = []
    left: list[LeftOut] = []
    seen: dict[str, tuple[str, str, str]] = {}
    for r in recs:
        obj, case, damage = str(r["object"]), str(r["case"]), str(r["damage"])
        cid = component_id(obj, case, damage)
        if cid in seen and seen[cid] != (obj, case, damage):
            raise IsorockError(
                f"export: {seen[cid]} and {(obj, case, damage)} both become the ID {cid}: rename one "
                "(an ID keeps letters, digits, '_' and '.')"
            )
        seen[cid] = (obj, case, damage)
        theta, beta = _float(r.get(median_col)), _float(r.get("beta"))
        estimable = bool(_float(r.get("estimable", 1)) == 1.0)
        if not estimable or not (math.isfinite(theta) and theta > 0 and math.isfinite(beta) and beta > 0):
            note = str(r.get("note") or "").strip()
            reason = note if note and note.lower() != "nan" else "not estimable: no finite median and beta"
            left.append(LeftOut(cid, obj, case, damage, reason))
            continue
        iso = r.get("isolation")
        base = f"base '{case}'" + (f" ({iso})" if isinstance(iso, str) and iso else "")
        counts = [_float(r.get(k)) for k in ("n_runs", "n_levels", "n_damaged")]
        data = (
            f"; maximum-likelihood fit to {counts[0]:.0f} runs at {counts[1]:.0f} stripes, "
            f"{counts[2]:.0f} damaged"
            if all(math.isfinite(v) for v in counts)
            else ""
        )
        ci_median = _interval(r, "median_ci95_g" if median_col == "median_g" else "median_ci95")
        said = (ctx.get("bases") or {}).get(case)
        if said:
            base += f", {said}"
        extra = ""
        if damage == "failure" and ctx.get("capacity_m") and said != "fixed base":
            extra += (
                f"; failure counts {ctx['gamma_x']:g} x the isolator's displacement beyond its capacity "
                f"{ctx['capacity_m']:g} m"
            )
        if ctx.get("top") is not None and theta > ctx["top"]:
            extra += (
                f"; the median lies beyond the highest stripe ({ctx['top']:g} {m.unit}): it is the fitted "
                "form's, not observed"
            )
        comment = (
            f"isorock {__version__}: {_WORDS.get(damage, damage)} of object '{obj}' on {base}; measure "
            f"{m.describe()} [{m.unit}], component definition {comp}{data}; 95 % bootstrap interval of "
            f"the median {ci_median}, of beta {_interval(r, 'beta_ci95')}{extra}; source {where}"
        )
        rows.append(
            {
                "ID": cid,
                "Incomplete": 0,
                "Demand-Type": demand_type(m),
                "Demand-Unit": pelicun_unit(m),
                "Demand-Offset": 0,
                "Demand-Directional": 1,
                "LS1-Family": "lognormal",
                "LS1-Theta_0": theta,
                "LS1-Theta_1": beta,
                "LS1-DamageStateWeights": "",
                "Comment": comment,
            }
        )
    return pd.DataFrame(rows, columns=list(PELICUN_COLUMNS)), left


def write_pelicun_csv(
    path: str | os.PathLike,
    source: str | os.PathLike | Mapping[str, pd.DataFrame] | pd.DataFrame | Any,
    **kw: Any,
) -> tuple[pd.DataFrame, list[LeftOut]]:
    """Write the fitted fragilities of an assessment as a pelicun damage model (CSV), atomically.

    Parameters
    ----------
    path : path-like
        The CSV file (its directory must exist; an existing file is replaced once the new one is
        complete: :func:`isorock.store.atomic_path`).
    source : path-like, Store, mapping or pandas.DataFrame
        As :func:`fragility_rows`.
    **kw
        ``imt``, ``component``, ``damages`` of :func:`fragility_rows`.

    Returns
    -------
    (pandas.DataFrame, list of LeftOut)
        The rows written and the fits left out.

    Raises
    ------
    IsorockError
        The directory does not exist, or ``path`` is a directory.
    """
    from isorock.store import atomic_path

    check_export_path(path)
    rows, left = fragility_rows(source, **kw)
    with atomic_path(path) as tmp:
        rows.to_csv(tmp, index=False, lineterminator="\n")  # every digit of the fit
    return rows, left


def check_export_path(path: str | os.PathLike) -> Path:
    """``path`` as a :class:`~pathlib.Path` if a file can be written there: its directory exists and it
    is not a directory itself (checked before a run, so that a wrong path does not cost one).

    Raises
    ------
    IsorockError
        One line that says which.
    """
    p = Path(path)
    if p.is_dir():
        raise IsorockError(f"--export-fragility {p}: is a directory; give a file name (fragility.csv)")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise IsorockError(f"--export-fragility {p}: the directory {parent} does not exist")
    return p
