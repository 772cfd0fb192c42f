"""How the verdict and the annual frequency of failure change with the scaling of the records.

For each worked example at a real site (``config/site-openquake.yaml``: an OpenQuake mean curve in
SA(0.15); ``config/site-usgs.yaml``: the USGS hazard service's curve in SA(1.0)), the same records and
bases are assessed three ways, each with the hazard curve of its own measure from the same source:

1. the worked example: the spectral measure, records scaled on the RotD50 of their two horizontals;
2. PGA, records scaled on the RotD50 of their two horizontals (the site's PGA curve);
3. PGA of the one component analysed (the site's PGA curve; ``assessment.component: analysed``), as
   isorock scaled records before it read the component definition.

Run from the repository's root with the Table 1 records::

    .venv/bin/python benchmarks/compare_scaling.py --records ../shared/records [--out DIR]

(about 3 minutes on 2 cores: six assessments). It prints, per site and scaling, each base's annual
frequency of failure with its 95 % interval, P(failure) at the MCE and the verdict's first sentence,
and writes them as JSON (``DIR/compare_scaling.json``).
"""

from __future__ import annotations

import argparse
import copy
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
HAZ = ROOT / "tests" / "data" / "hazard"

#: site -> (worked example, {scaling name: changes to its assessment section})
STUDIES = {
    "openquake": (
        "config/site-openquake.yaml",
        {
            "SA(0.15) RotD50": {},
            "PGA RotD50": {
                "imt": "PGA",
                "hazard": {"openquake": str(HAZ / "case_19" / "hazard_curve-mean_PGA.csv"), "site": 0},
            },
            "PGA analysed": {
                "imt": "PGA",
                "component": "analysed",
                "hazard": {"openquake": str(HAZ / "case_19" / "hazard_curve-mean_PGA.csv"), "site": 0},
            },
        },
    ),
    "usgs": (
        "config/site-usgs.yaml",
        {
            "SA(1.0) RotD50": {},
            "PGA RotD50": {"imt": "PGA", "hazard": {"usgs": str(HAZ / "dwight_7th.json"), "imt": "PGA"}},
            "PGA analysed": {
                "imt": "PGA",
                "component": "analysed",
                "hazard": {"usgs": str(HAZ / "dwight_7th.json"), "imt": "PGA"},
            },
        },
    ),
}

#: PGA stripes [g] of the PGA variants (the spectral ones keep the worked example's)
PGA_STRIPES = [0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0, 1.2]


def _config(example: str, changes: dict) -> dict:
    cfg = yaml.safe_load((ROOT / example).read_text())
    a = cfg["assessment"]
    hz = copy.deepcopy(a["hazard"])
    for k in ("openquake", "usgs"):
        if k in hz:
            hz[k] = str(ROOT / hz[k])
    a["hazard"] = hz
    a.update(copy.deepcopy(changes))
    if changes.get("imt") == "PGA":
        a["stripes_g"] = PGA_STRIPES
    return cfg


def _one(cfg: dict, records: str, work: Path) -> dict:
    work.mkdir(parents=True, exist_ok=True)
    path = work / "config.yaml"
    path.write_text(yaml.safe_dump(cfg, sort_keys=False))
    exe = Path(sys.executable).with_name("isorock")
    cmd = [str(exe), "assess", str(path), "--cores", "2", "--records", records, "--json"]
    out = subprocess.run(cmd, cwd=work, capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{out.stderr[-2000:]}")
    s = json.loads(out.stdout)
    rows = []
    for c in s["cases"]:
        h = c.get("hazard") or {}
        d = (c.get("design_levels") or [{}])[0]
        rows.append(
            {
                "case": c["isolation"],
                "annual_rate_failure": h.get("annual_rate_failure"),
                "annual_rate_failure_ci95": h.get("annual_rate_failure_ci95"),
                "p_failure_mce": d.get("p_failure_mce"),
                "design_level": d.get("level"),
                "mce_level": d.get("mce_g"),
            }
        )
    v = s["design"][0] if s.get("design") else {}
    return {
        "imt": s.get("imt"),
        "component": s.get("component"),
        "verdict": v.get("verdict"),
        "headline": s["conclusions"][0]["headline"] if s.get("conclusions") else "",
        "cases": rows,
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--records", required=True, help="the Table 1 records (../shared/records)")
    p.add_argument("--out", default=None, help="where to keep the runs (default: a temporary folder)")
    a = p.parse_args(argv)
    base = Path(a.out) if a.out else Path(tempfile.mkdtemp(prefix="isorock-scaling-"))
    result: dict = {}
    for site, (example, variants) in STUDIES.items():
        for name, changes in variants.items():
            print(f"{site}: {name} ...", flush=True)
            r = _one(
                _config(example, changes),
                str(Path(a.records).resolve()),
                base / site / name.replace(" ", "_"),
            )
            result.setdefault(site, {})[name] = r
            for c in r["cases"]:
                rate, ci = c["annual_rate_failure"], c["annual_rate_failure_ci95"] or [None, None]
                pm = c["p_failure_mce"]
                print(
                    f"  {c['case']:5s} design {c['design_level']:.3g}, MCE {c['mce_level']:.3g}: "
                    f"failures/yr {rate:.2e} ({ci[0]:.2e} to {ci[1]:.2e}), "
                    f"P(failure | MCE) {'-' if pm is None else f'{100 * pm:.3g} %'}"
                )
            print(f"  verdict {r['verdict']}: {r['headline'][:160]}")
    (base / "compare_scaling.json").write_text(json.dumps(result, indent=1))
    print(f"written: {base / 'compare_scaling.json'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
