"""HDF5 store: self-describing results, written atomically.

The workflow (``Snakefile``, :mod:`isorock.pipeline`) writes one HDF5 file per job under ``results/``
and merges them into ``results/isorock.h5``. Modules: :mod:`~isorock.store.layout` (names, columns,
units), :mod:`~isorock.store.atomic` (atomic writes, hashes), :mod:`~isorock.store.hdf` (attributes,
pandas tables, dimension scales, merging), :mod:`~isorock.store.maps` (regime maps and their index) and
:mod:`~isorock.store.reader` (:class:`Store`, the one reader the figures and the report use).
Every file is written under a temporary name in the same directory and renamed when complete
(:func:`atomic_path`, :func:`atomic_h5`), so a killed or failed run never leaves a file under the
final name that looks complete.

Reading
-------
Groups, arrays and attributes are plain HDF5 (``h5py``); every table is also a pandas table
(``pandas.read_hdf(path, key)``, PyTables ``format="table"``). Units are in the attribute ``units``
of a dataset, in the column names (``_g``, ``_m``, ``_s``, ``_m_s``, ``_rad_s``; ``lambda_``,
``xi_b`` and ``rho`` are dimensionless) and, for tables, in the JSON attribute ``units`` of the
table's group. Missing numbers are NaN. Names that are Python keywords get a trailing underscore
(the slenderness is ``lambda_``) and boolean attributes are stored as 0 / 1, so that pandas reads
the summary and pulse tables without a PyTables warning. Record ids such as ``IMV79-EMO`` are not
Python identifiers: reading ``/overturn/<id>`` by key may make PyTables warn (``NaturalNameWarning``;
PyTables 3.11 does not) and the warning is harmless; ``/summary/overturn`` holds the same rows.

The arrays are also netCDF-4 variables (layout 5): their axes are HDF5 dimension scales, so that
``xarray.open_datatree(path, engine="h5netcdf")`` opens the whole store without a warning, with named
dimensions and coordinates (units in the attribute ``units``): a map's ``codes`` and
``max_theta_over_alpha`` along ``lambda_`` and ``R_m``, or ``Tb_s`` and ``xi_b`` (its grid); a record's
``acc`` and ``vertical`` along ``time_s`` [s]; the lines of ``processing`` along ``line``, a dimension
without values. A pandas table is the variable ``table`` (one record per row, the columns as fields) of
dimension ``row``; read tables with pandas. ::

    import xarray as xr
    tree = xr.open_datatree("results/isorock.h5", engine="h5netcdf")
    m = tree["maps/pulse-fullsine-td0.5/lambda_R-linear"]     # codes (lambda_, R_m)
    m["codes"].sel(lambda_=4.0, R_m=3.0, method="nearest")

HDF5 attaches no dimension scale to a PyTables table (``H5DSattach_scale`` refuses a dataset of class
``TABLE``; and PyTables, hence pandas, could not read a table carrying the reference attribute
``DIMENSION_LIST``): each table group holds instead ``row``, a dimension without values as long as the
table, and netCDF-4 readers give an axis without a scale the dimension of its group that has its length
(h5netcdf always; netCDF-C only when both are unlimited or both fixed, so that ``ncdump`` names the
tables' axis ``phony_dim_N``). PyTables does not read attributes that hold HDF5 references
(PyTables issue 132), which dimension scales carry (``DIMENSION_LIST``, ``REFERENCE_LIST``): what
opens every dataset with PyTables fails on the store (pandas' ``HDFStore.walk()`` and
``HDFStore.keys(include="native")`` raise ``KeyError: 'Reference'`` with PyTables 3.11; ``ptdump``,
``ptrepack``); pandas' ``read_hdf``, ``HDFStore.keys()``, ``select`` and ``info()``, which open the
tables only, read them without a warning.

Layout of ``results/isorock.h5`` (``layout_version`` 5)
--------------------------------------------------------
::

    /                                   attrs: isorock_version, layout_version, config_name (the
                                        configuration file's name), config_hash (sha256 of
                                        the validated configuration, canonical JSON), config_json,
                                        created_utc, outcome_legend, record_source (where the records
                                        came from: "records directory DIR" | "pyslammer samples"),
                                        job_files_json (the job files it was merged from, relative to
                                        the run folder: a run finds one deleted and merges again), and
                                        the software of the merge (isorock.environment.store_attrs;
                                        isorock info --versions prints the same): version_python,
                                        version_numpy, version_scipy, version_numba, version_llvmlite,
                                        version_obspy, version_h5py, version_pandas, version_snakemake
                                        (text: the version, or "not installed"), platform
                                        (platform.platform()), platform_machine (e.g. "x86_64")
    /records/<id>                       one group per record (process_record, extract_pulse)
        attrs                           the RECORD_ATTRS of isorock.store.layout (name, unit, kind,
                                        description; describe_record_attrs() prints them): identity,
                                        component analysed and how it was obtained, source files,
                                        intensity measures, Tp, Table 1 values, QA, processing_json
        time_s              (npts,)     sample times k dt [s], the dimension scale (coordinate) of acc
                                        and vertical; attrs units, long_name, dt_s (layout 5)
        acc                 (time_s)    processed ground acceleration [m/s^2]; attrs units, dt_s
        line                (n,)        the dimension of processing: no values (layout 5)
        processing          (line)      processing history for people, one line per step (str;
                                        a rotation of two components adds its line first)
        vertical            (time_s)    processed vertical acceleration, positive up [m/s^2], on the
                                        samples of acc; only where one was found (vertical_note);
                                        attrs positive_in_file (up/down: the sense of the file's
                                        samples), sign (+1/-1 applied) and polarity (why; issue 34)
        pulse/                          attrs: isorock.pulse.PulseResult.summary() (Tp_s, Tp_mp_s, mp_*, ...)
            time_s          (npts,)     the sample times of acc again (written by extract_pulse)
            velocity        (time_s)    ground velocity [m/s]
            pulse_velocity  (time_s)    extracted (db4 wavelet) velocity pulse [m/s]
            mp_velocity     (time_s)    fitted Mavroeidis-Papageorgiou pulse [m/s]
    /overturn/<id>                      pandas table, one row per (lambda, R, isolation case)
    /maps/<source>/<map>                a response-regime map (write_map layout below)
    /pulses/overturn_R                  pandas table: min. overturning amplitude vs R (Figs 4, 7 left)
    /pulses/overturn_omega              pandas table: the same vs omega_p (Figs 4, 7 right)
    /pulses/overturn_isolation          pandas table: vs Tb, xi_b, rho for the full-sine pulse (Fig 5)
    /pulses/restitution                 pandas table: eps and beta1/h vs lambda for several rho (Fig 3)
    /summary/records                    pandas table: one row per record (the /records attrs, no arrays)
    /summary/overturn                   pandas table: all /overturn/<id> tables stacked (column ``record``;
                                        with_vertical, min_overturn_h_g, min_overturn_hv_g: the search
                                        horizontal only and with the record's vertical)
    /summary/maps                       pandas table: one row per map (MAP_INDEX_COLUMNS)
    /assessment/objects                 pandas table: the objects assessed (object, lambda_, R_m, height_m,
                                        width_m, friction, tan_alpha, mode (rocking or sliding: friction
                                        below tan_alpha), slide_allow_m [m])
    /assessment/measure                 one row: the stripes' measure (imt, OpenQuake's string; unit g or
                                        cm/s), its component definition (component: RotD50, RotD100,
                                        analysed), label, basis (why), and the hazard curve's hazard_imt,
                                        hazard_component_definition, hazard_source (in words),
                                        hazard_file, hazard_kind, hazard_site, hazard_vs30_m_s [m/s],
                                        hazard_notes (JSON); the group /assessment has the attributes
                                        imt, component, unit (layout 7)
    /assessment/runs                    every full run: object, case, record, level (in the measure of
                                        /assessment/measure; layout 6 and older: pga_g), pga_g (the
                                        analysed component's PGA at that level [g]), scale, outcome,
                                        outcome_code, max_theta_over_alpha, max_base_disp_m [m],
                                        mu_required, min_normal_over_weight, slides, jumps, outside_model,
                                        decided, stripe, design (0/1); mode, sliding_peak_m,
                                        sliding_residual_m [m], n_slips, slide_allow_m [m] (a sliding
                                        object's runs; NaN otherwise), exceeds_capacity (gamma_x times the
                                        displacement beyond capacity_m), slides_beyond, overturn, uplift,
                                        failure (0/1); candidate, source (floor, case, grid), isolation,
                                        Tb_s, xi_b, mu_b, R_b_m, rho: the base. The design search's fixed
                                        base and grid isolators have case design/<candidate>: every verdict
                                        can be recomputed from this table and the configuration
    /assessment/first_overturn          object, case, record, record_pga_g, min_overturn_g, uplift_g,
                                        resolution (the minimum-overturning search of every record);
                                        for a body whose sides differ also min_overturn_as_recorded_g,
                                        min_overturn_reversed_g (min_overturn_g is the smaller)
    /assessment/stripes                 object, case, isolation, level, n_records, n_overturn, n_uplift,
                                        n_exceed_capacity, n_failure, n_outside_model, n_slides, n_jumps,
                                        n_slid, n_slides_beyond, slide_median_m, slide_p84_m, slide_max_m,
                                        disp_median_m, disp_p84_m, disp_mean_m, disp_max_m
    /assessment/fragility               object, case, isolation, damage (overturn, failure, uplift), median_g
                                        (in the stripes' measure: g, or cm/s for PGV), beta and their 95 %
                                        intervals (_lo, _hi; NaN where not estimable: see note), n_levels,
                                        n_runs, n_damaged, note, n_boot, n_boot_fitted
    /assessment/fragility_band          the fitted curves and their 95 % bands on a grid of levels
    /assessment/fragility_by_measure    per case and damage: median, beta and their 95 % intervals under
                                        PGA, PGV and SA at the isolation period of the analysed component
                                        (measure named OpenQuake's way, component analysed)
    /assessment/design_levels           per case and design level: p_overturn, p_failure, p_uplift with
                                        intervals, the observed fractions with exact bounds, the records
                                        beyond the capacity (p_exceed_capacity and interval), the MCE check
                                        (disp_mce_m and interval, p_mce_exceed_capacity and interval,
                                        mce_within_capacity, mce_basis), design_basis
    /assessment/hazard                  with a hazard curve: annual_rate with its interval and its two tails
                                        (annual_rate_bounds_lo/_hi), p50, p_at_first, method
    /assessment/validity                object, case, isolation, friction, n_runs, n_slides, n_jumps,
                                        n_outside_model, mu_required_max
    /assessment/design                  every candidate per object and design level: isolation and its
                                        parameters, estimate and interval, eligible, rank (0 not eligible),
                                        target_estimate, adequate, p_failure_mce and its interval,
                                        vs_floor_* and vs_best_* (the paired differences: difference and its
                                        interval, p_better, p_worse, p_adjusted), beats_floor, equivalent,
                                        recommended
    /assessment/verdicts                per object and design level: verdict (isolate, fixed_base,
                                        restrain, inconclusive), reason, target (JSON), recommended, best,
                                        closest, n_records,
                                        records_to_decide, the design and MCE levels with their bases, grid
                                        (JSON: extended, bounds_reached, axes, configured)

Map names. ``<source>`` is a record id or ``pulse-<shape>-td<td_s>`` (e.g. ``pulse-fullsine-td0.5``,
Fig 6). ``<map>`` is ``lambda_R-<case>`` (lambda-R plane, Figs 6, 9, 10, 13; ``<case>`` an isolation
case name of the configuration, e.g. ``none``, ``linear``, ``fp``) or ``Tb_xi-lam<lambda>-R<R_m>``
(Tb-xi plane for a linear isolator, Figs 11, 12), numbers formatted with ``%g``. Select maps by the
columns of ``/summary/maps`` (or the group attributes) rather than by name: the case names are the
user's.

A map group (:func:`write_map`) holds the datasets of its axes (``lambda_`` [-] and ``R_m`` [m], or
``Tb_s`` [s] and ``xi_b`` [-]; the attributes ``x_name``, ``y_name`` name them ``lambda``, ...; each a
dimension scale with the attributes ``units`` and ``long_name``, layout 5), ``codes`` (int8, shape
(len(x), len(y)), dimensions (x, y); 0 = no uplift, 1 = rocking, 2 = overturn) and
``max_theta_over_alpha`` (partial where the outcome was decided early; dimensions (x, y)), with
attributes ``kind``
("lambda-R" | "Tb-xi"), ``x_name``, ``y_name``, ``amp_g`` (excitation PGA [g]), ``fixed`` (JSON of the
fixed parameters: isolation kind and its parameters, or lambda, R_m, rho) plus ``fixed_<name>``
copies, ``n_analyses``, ``seconds``; a map written by ``isorock map --out`` adds its inputs
(``source``, ``source_kind``, ``pulse_shape`` and ``td_s``, or ``record_file``, ``record_sha256``,
``record_format``, ``record_units``, ``record_component``, ``record_processing``); maps written by the
workflow add ``source``, ``map``, ``source_kind`` ("record" | "pulse"), ``case``, ``amp_source``
("table1" | "record" | "config" | "pulse"), ``pulse_shape`` and ``td_s`` (pulses) or ``record_sha256``
(records), ``config_hash``.

Table columns
-------------
Every table group has the attributes ``units`` (JSON: column -> unit) and ``columns`` (JSON list), and
beside the table the dataset ``row`` (the table's dimension for xarray, no values; layout 5);
``/overturn/<id>`` also ``record``, ``record_sha256``, ``record_pga_g``, ``Tp_s``, ``config_hash``,
``search`` (JSON: amp_max_g, growth, rtol), ``isorock_version``; the pulse tables ``config_hash``,
``search``, ``lambda`` and ``isorock_version``.

``/overturn/<id>`` and ``/summary/overturn`` (:data:`OVERTURN_COLUMNS`): ``record``, ``lambda_``,
``R_m``, ``b_m``, ``h_m``, ``tan_alpha``, ``case``, ``isolation`` ("none" | "linear" | "fp"),
``Tb_s``, ``xi_b``, ``rho``, ``mu_b``, ``R_b_m`` (NaN where they do not apply; ``Tb_s`` of an FP
isolator is its pendulum period), ``min_overturn_g`` (smallest PGA that overturns the block [g],
NaN when nothing up to ``amp_max_g`` does), ``overturns`` (bool), ``min_overturn_over_tan_alpha``,
``uplift_g`` (PGA at which rocking starts [g]), ``uplift_over_tan_alpha``, ``n_analyses``,
``amp_max_g``, ``resolution`` (relative uncertainty of ``min_overturn_g``: the scan step,
``growth - 1``), ``stalls`` (uplifts the engine's zero-progress guard skipped, 0 in a sound
search), ``record_pga_g`` (PGA of the processed record [g]), ``scale_min`` (``min_overturn_g
/ record_pga_g``: the scale factor of the record that first overturns the block).

``/pulses/overturn_R``, ``/pulses/overturn_omega``, ``/pulses/overturn_isolation``
(:data:`PULSE_COLUMNS`): ``pulse`` ("rect" | "halfsine" | "fullsine"), ``td_s``, ``omega_p_rad_s``
(``pi / td``), ``series`` (which curve family the row belongs to: ``"td"`` (curves of fixed td),
``"R"`` (curves of fixed R)), ``param`` (``/pulses/overturn_isolation`` only: the varied
isolation parameter, "Tb_s" | "xi_b" | "rho", or "none" for the non-isolated reference rows;
"" elsewhere), ``value`` (its value, NaN elsewhere), then the block and isolation columns and the
results as in ``/overturn`` (without ``record``, ``record_pga_g``, ``scale_min``). The amplitudes
are pulse amplitudes ``A_g0`` [g].

``/pulses/restitution`` (Fig 3): ``lambda_``, ``rho``, ``eps`` (angular restitution [-]),
``beta1_over_h`` (``beta1 / h`` [-]), ``eps_housner`` (rigid base, [-]).

``/summary/maps`` (:data:`MAP_INDEX_COLUMNS`): ``path`` (HDF5 path of the map group), ``source``,
``source_kind``, ``map``, ``kind``, ``case``, ``isolation``, ``Tb_s``, ``xi_b``, ``rho``, ``mu_b``,
``R_b_m``, ``lambda_``, ``R_m`` (Tb-xi maps: the block), ``pulse``, ``td_s``, ``amp_g``,
``amp_source``, ``nx``, ``ny``, ``no_uplift``, ``rocking``, ``overturn`` (counts of grid points),
``n_analyses``, ``seconds``.

``/summary/records`` (:data:`RECORD_SUMMARY_COLUMNS`): ``record`` (the id), then the
:data:`RECORD_ATTRS` marked ``summary``, in their order (text and JSON as str, flags as bool).

Record attributes
-----------------
:data:`RECORD_ATTRS` (:class:`RecordAttr` entries: ``name``, ``unit``, ``description``, ``kind``, the
``job`` that writes it, ``summary``) is the one spec of the attributes of ``/records/<id>``: the
workflow's ``process_record`` and ``extract_pulse`` write exactly its entries
(:func:`record_attrs_in_order`), the merge copies the ``extract_pulse`` ones from the pulse group and
builds ``/summary/records`` from it. ``processing_json`` (layout 3) is the processing of the record, a
JSON list of ``{"step", "parameters", "note"}`` objects in the order applied
(:class:`isorock.processing.AppliedStep`; parameters in the units of the step).

Layout versions
---------------
:data:`LAYOUT_HISTORY` says what each version changed. Version 3 added ``processing_json``; a store of
version 2 has only the ``processing`` lines. :meth:`Store.record_processing` reads both
(:func:`isorock.store.reader.processing_steps`, the one place that reads an older layout). Version 5
added the dimension scales (``time_s``, ``line``, ``row``, the map axes as scales) and changed no
dataset that was there: the readers of isorock read a store of version 2 to 4 as before; xarray opens
one with a warning and ``phony_dim_N`` dimensions (pass ``phony_dims="sort"``). The merge
(:func:`merge_h5`) attaches the scales of the job files again in the store; job files written before
version 5 bring their arrays without scales.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the names below are imported on first use (:func:`__getattr__`)
    from isorock.store.atomic import atomic_h5, atomic_path, config_hash, file_sha256, locked, stamp, try_lock
    from isorock.store.hdf import (
        NOT_A_VARIABLE,
        attach_dims,
        attr,
        attrs_dict,
        coordinate,
        dimension,
        merge_h5,
        read_table,
        set_attrs,
        time_coordinate,
        write_tables,
    )
    from isorock.store.layout import (
        COLUMN_UNITS,
        LAYOUT_HISTORY,
        LAYOUT_VERSION,
        MAP_INDEX_COLUMNS,
        OUTCOME_LEGEND,
        OVERTURN_COLUMNS,
        PULSE_COLUMNS,
        RECORD_ATTRS,
        RECORD_SUMMARY_COLUMNS,
        RESTITUTION_RHOS,
        RecordAttr,
        describe_record_attrs,
        record_attr_names,
        record_attrs_in_order,
        restitution_table,
    )
    from isorock.store.maps import map_index, map_index_row, map_paths, read_map, write_map
    from isorock.store.reader import MapInfo, Store, StoreNotFound, processing_steps

#: the modules of this package, in the order :func:`__getattr__` looks a name up in their ``__all__``
_MODULES = ("atomic", "hdf", "layout", "maps", "reader")

__all__ = [
    "LAYOUT_VERSION",
    "LAYOUT_HISTORY",
    "OUTCOME_LEGEND",
    "OVERTURN_COLUMNS",
    "PULSE_COLUMNS",
    "MAP_INDEX_COLUMNS",
    "RECORD_SUMMARY_COLUMNS",
    "COLUMN_UNITS",
    "RecordAttr",
    "RECORD_ATTRS",
    "record_attr_names",
    "record_attrs_in_order",
    "describe_record_attrs",
    "RESTITUTION_RHOS",
    "restitution_table",
    "atomic_path",
    "atomic_h5",
    "try_lock",
    "locked",
    "stamp",
    "config_hash",
    "file_sha256",
    "set_attrs",
    "attr",
    "attrs_dict",
    "write_tables",
    "read_table",
    "NOT_A_VARIABLE",
    "coordinate",
    "dimension",
    "time_coordinate",
    "attach_dims",
    "merge_h5",
    "write_map",
    "read_map",
    "map_paths",
    "map_index",
    "map_index_row",
    "Store",
    "MapInfo",
    "StoreNotFound",
    "processing_steps",
]


def __getattr__(name: str) -> Any:
    """A public name of the store, imported from its module on first use (PEP 562): the tables and
    HDF5 modules need pandas, PyTables and h5py (about 0.3 s to import), which the record checksum
    (:func:`file_sha256`) and the atomic writes (:func:`atomic_path`) of :mod:`isorock.records` do not."""
    if name in __all__:
        modules = []
        for mod in _MODULES:  # the module that exports the name ...
            modules.append(importlib.import_module(f".{mod}", __name__))
            if name in getattr(modules[-1], "__all__", ()):
                break
        for module in reversed(modules):  # ... else one that defines it
            if hasattr(module, name):
                value = getattr(module, name)
                globals()[name] = value
                return value
    if name in _MODULES:  # a submodule as an attribute (isorock.store.hdf), as before it was lazy
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
