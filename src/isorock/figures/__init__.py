"""The paper's figures (Figs 3-13) and one figure per record, drawn from the HDF5 store.

Every function reads only the store (layout in :mod:`isorock.store`), writes one image (the format
follows the suffix of ``out_path``: ``.png``, ``.pdf``, ``.svg``) with matplotlib's Agg canvas (no
pyplot, no global backend change) and returns its path; when the data it needs are not in the
store it writes nothing, logs one line saying what is missing (logger ``isorock.figures``, level
WARNING) and returns None.

==========  ===================================================================================
figure      data read from the store
==========  ===================================================================================
Fig 3       ``/pulses/restitution`` (``lambda``, ``rho``, ``eps``, ``beta1_over_h``); when absent the
            closed forms of :func:`isorock.physics.model.impact_coefficients` (no analysis needed)
Fig 4       ``/pulses/overturn_R`` (``series == "td"``) and ``/pulses/overturn_omega``
            (``series == "R"``): the three pulses, ``isolation`` "none" and "linear"
Fig 5       ``/pulses/overturn_isolation`` (``param`` "Tb_s" / "xi_b" / "rho" / "none"): full-sine
            pulse, curves of fixed ``R`` (``series == "R"``) and of fixed ``td`` (``series == "td"``)
Fig 6       lambda-R maps of pulse sources (``/maps/pulse-<shape>-td<td>/lambda_R-<case>``)
Fig 7       as Fig 4, full-sine pulse, ``isolation`` "linear" against "fp"
Fig 8       ``/overturn/<id>`` (or ``/summary/overturn``) of the records BRI, EMO, PKC, CH3W
Figs 9, 10  lambda-R maps of the records TAB, EMO, CH3W, PKC (9) and C02, NWS, AEG-L, AEG-T (10)
Fig 11      Tb-xi maps (``lambda`` 4, ``R`` 6 m) of the records BRI, EMO, CH3W, PKC
Fig 12      Tb-xi maps of the PKC record with ``lambda`` 3, one panel per ``R``
Fig 13      lambda-R maps, linear against FP isolator, records EMO and E05
record      ``/records/<id>/acc`` (attr ``dt_s``) and ``/records/<id>/pulse/{velocity,
            pulse_velocity, mp_velocity}``; also accepted: ``vel``, ``pulse_vel`` and attr ``dt``
overturn    ``/overturn/<id>`` and the record's PGA: every record (``overturn_<id>.png``)
maps        every map of ``/maps/<id>``: every record (``maps_<id>.png``)
assessment  ``/assessment/*``: fragility curves, displacement demand and design chart per object
==========  ===================================================================================

Maps are found by their group attributes (``kind``, ``source``, ``source_kind``, ``isolation``,
``pulse_shape``, ``td_s``, ``lambda``, ``R_m``, the ``fixed`` JSON), not by their names; records by
their catalog ids (``NOR94-PKC``), or by the station code when the store uses other ids. Regime maps
use the paper's colours: cyan no uplift, green rocking, red overturning.

Example
-------
>>> from isorock.figures import make_all
>>> paths = make_all("results/isorock.h5", "results/figures")  # doctest: +SKIP
"""

from __future__ import annotations

import functools
import os
import re
from collections.abc import Callable
from pathlib import Path

from isorock.figures.assessment import fig_design, fig_displacement, fig_fragility, fig_modes, fig_sliding
from isorock.figures.pulses import fig_3, fig_4, fig_5, fig_6, fig_7
from isorock.figures.records import (
    fig_8,
    fig_9,
    fig_10,
    fig_11,
    fig_12,
    fig_13,
    fig_record,
    fig_record_maps,
    fig_record_overturn,
)
from isorock.figures.style import REGIME_COLORS, REGIME_LABELS, log
from isorock.parallel import fork_map
from isorock.store import Store, StoreNotFound

__all__ = [
    "REGIME_COLORS",
    "REGIME_LABELS",
    "fig_3",
    "fig_4",
    "fig_5",
    "fig_6",
    "fig_7",
    "fig_8",
    "fig_9",
    "fig_10",
    "fig_11",
    "fig_12",
    "fig_13",
    "fig_record",
    "fig_record_overturn",
    "fig_record_maps",
    "fig_fragility",
    "fig_modes",
    "fig_displacement",
    "fig_design",
    "make_all",
    "FIGURES",
    "FIGURE_GROUPS",
    "figure_group",
]


#: figure number -> (function, file name)
FIGURES: dict[int, tuple[Callable[..., Path | None], str]] = {
    3: (fig_3, "fig03_restitution.png"),
    4: (fig_4, "fig04_overturn_pulses.png"),
    5: (fig_5, "fig05_isolation_parameters.png"),
    6: (fig_6, "fig06_maps_pulses.png"),
    7: (fig_7, "fig07_linear_vs_fp.png"),
    8: (fig_8, "fig08_overturn_records.png"),
    9: (fig_9, "fig09_maps_records.png"),
    10: (fig_10, "fig10_maps_records.png"),
    11: (fig_11, "fig11_maps_Tb_xi.png"),
    12: (fig_12, "fig12_maps_Tb_xi_R.png"),
    13: (fig_13, "fig13_maps_linear_fp.png"),
}


#: file-name prefix -> the group of the figure (a subcategory of the report's 'Figures')
FIGURE_GROUPS: dict[str, str] = {
    "fig": "Paper figures (Figs 3-13)",
    "record_": "Per record: ground motion and pulse",
    "overturn_": "Per record: minimum overturning PGA",
    "maps_": "Per record: regime maps",
    "assessment_": "Assessment",
}


def figure_group(name: str) -> str:
    """The group of a figure file (name with or without ``.png``): :data:`FIGURE_GROUPS`, else 'Other'."""
    return next((g for prefix, g in FIGURE_GROUPS.items() if name.startswith(prefix)), "Other")


def make_all(
    h5_path: str | os.PathLike,
    outdir: str | os.PathLike,
    *,
    workers: int = 1,
    finish: Callable[[Path], None] | None = None,
) -> list[Path]:
    """Draw every figure whose data are in the store, and one figure per record.

    Parameters
    ----------
    h5_path : path-like
        The store (``results/isorock.h5``).
    outdir : path-like
        Directory of the images (created): ``fig03_restitution.png`` ... ``fig13_*.png``,
        ``record_<id>.png``, ``overturn_<id>.png``, ``maps_<id>.png`` per record and
        ``assessment_{fragility,modes,displacement,design}_<object>.png`` per assessed object.
    workers : int
        Processes that draw at once (each figure is independent; the store is only read).
    finish : callable, optional
        Applied to each image written, in the process that drew it (e.g. a PNG size reduction).

    Returns
    -------
    list of Path
        The images written, in the order above (figures skipped for want of data are logged, not
        listed).
    """
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    tasks: list[tuple[Callable[..., Path | None], tuple]] = [
        (fn, (h5_path, outdir / name)) for fn, name in FIGURES.values()
    ]
    try:
        ids = Store(h5_path).record_ids()
    except StoreNotFound as exc:
        log.warning("record figures skipped: %s", exc)
        ids = []
    per_record = ((fig_record, "record"), (fig_record_overturn, "overturn"), (fig_record_maps, "maps"))
    per_object = (
        (fig_fragility, "assessment_fragility"),
        (fig_modes, "assessment_modes"),
        (fig_displacement, "assessment_displacement"),
        (fig_design, "assessment_design"),
        (fig_sliding, "assessment_sliding"),
    )
    for names, drawers in ((ids, per_record), (_assessed_objects(h5_path), per_object)):
        for name in names:
            safe = re.sub(r"[^0-9A-Za-z_.+-]", "_", name)
            for fn, prefix in drawers:
                tasks.append((fn, (h5_path, name, outdir / f"{prefix}_{safe}.png")))
    # forked workers start with matplotlib and the package already imported
    done = fork_map(functools.partial(_draw, finish=finish), tasks, workers)
    return [p for p in done if p is not None]


def _draw(
    task: tuple[Callable[..., Path | None], tuple], finish: Callable[[Path], None] | None
) -> Path | None:
    fn, args = task
    p = fn(*args)
    if p is not None and finish is not None:
        finish(Path(p))
    return p


def _assessed_objects(h5_path: str | os.PathLike) -> list[str]:
    try:
        objs = Store(h5_path).table("assessment/objects")
    except StoreNotFound:
        return []
    return [] if objs is None else [str(o) for o in objs["object"]]
