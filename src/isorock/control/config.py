"""The workflow configuration: one loader and one validator, used by the Snakefile, the CLI and the tests.

A configuration is YAML (``config/*.yaml``) checked against the JSON Schema
``workflow/schemas/config.schema.yaml``, which also gives the defaults. :func:`validate_config` fills
the defaults in, checks that every number is finite (YAML ``.nan`` and ``.inf`` pass the schema's
bounds), the schema, and what the schema cannot express (isolation case names exist and are unique;
every isolator, pulse duration and grid within the bounds of :mod:`isorock.plausibility`, the command
line's) and raises :class:`~isorock.errors.ConfigError` with one line naming the key and what it must
be (for a ``oneOf``, the violation of the alternative the value is meant as). The
Snakefile calls it on the configuration Snakemake has merged, so that the plain ``snakemake
--configfile`` route stops before any job; :func:`load_config` does the same merge outside Snakemake
(``isorock report``, the tests).

jsonschema is used directly rather than ``snakemake.utils.validate`` (which wraps it the same way)
because the package reads configurations without Snakemake installed and reports the first
violation in one line. Lengths in m, times in s, accelerations in g.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import jsonschema
import yaml

import isorock.resources as resources
from isorock.control.bounds import (
    DESIGN_AXES,
    check_finite_tree,
    check_grid_values,
    check_string_lengths,
    check_values,
    refuse,
)
from isorock.control.grids import grid_ends, grid_size, grid_values
from isorock.errors import ConfigError, ParameterError
from isorock.physics.model import Isolation, NoIsolation, make_isolation
from isorock.plausibility import check_isolator, check_object

__all__ = [
    "IsolationCase",
    "load_config",
    "workflow_config",
    "studies_default",
    "apply_studies_default",
    "merge_config",
    "validate_config",
    "grid_values",
    "grid_size",
    "grid_ends",
    "isolation_cases",
    "case_dict",
    "case_from",
    "ref_name",
    "ref_applies",
]


def _defaulting_validator(schema: dict):
    """A jsonschema validator that fills in ``default`` values (as ``snakemake.utils.validate`` does)."""
    base = jsonschema.validators.validator_for(schema)

    def set_defaults(validator, properties, instance, schema):
        if isinstance(instance, dict):
            for prop, sub in properties.items():
                if "default" in sub:
                    instance.setdefault(prop, copy.deepcopy(sub["default"]))
        yield from base.VALIDATORS["properties"](validator, properties, instance, schema)

    return jsonschema.validators.extend(base, {"properties": set_defaults})(schema)


#: the schema last loaded by :func:`validate_config` (for the descriptions in messages)
_ROOT: dict[str, Any] = {}
_BOUNDS = {"exclusiveMinimum": "> {}", "minimum": ">= {}", "exclusiveMaximum": "< {}", "maximum": "<= {}"}


def _range(sch: Mapping) -> str:
    """``"> 0 and < 1"`` from a property's schema ("" when it has no bounds)."""
    return " and ".join(_BOUNDS[k].format(sch[k]) for k in _BOUNDS if k in sch)


def _property_schema(root: Mapping, path: Sequence[Any], name: str) -> Mapping:
    """The schema of property ``name`` of the object the schema path ``path`` leads into ({} if none)."""
    node: Any = root
    found: Mapping = {}
    for step in path:
        if isinstance(node, Mapping) and isinstance(node.get("properties"), Mapping):
            found = node["properties"].get(name, found)
        try:
            node = node[step]
        except (KeyError, IndexError, TypeError):
            break
    return found if isinstance(found, Mapping) else {}


_TYPES = {"number": "a number", "integer": "an integer", "string": "a string", "array": "a list",
          "object": "a mapping", "boolean": "true or false", "null": "null"}  # fmt: skip


def _kind(sch: Any) -> str:
    """What a value of schema ``sch`` is, in words: ``a number > 0``, ``one of table1, record``, ``a
    mapping with start, stop, num``."""
    if not isinstance(sch, Mapping):
        return "a value"
    if "enum" in sch:
        return "one of " + ", ".join(map(str, sch["enum"]))
    types = sch.get("type", [])
    types = [types] if isinstance(types, str) else list(types)
    words = []
    for t in types:
        w = _TYPES.get(t, t)
        if t in ("number", "integer") and _range(sch):
            w += " " + _range(sch)
        elif t == "array" and isinstance(sch.get("items"), Mapping) and "type" in sch["items"]:
            w = "a list of " + _kind(sch["items"]).removeprefix("a ").removeprefix("an ")
            w = w.replace("number", "numbers", 1).replace("string", "strings", 1)
        elif t == "object" and sch.get("required"):
            w += " with " + ", ".join(sch["required"])
        words.append(w)
    return " or ".join(words) or "a value"


def _alternatives(sch: Mapping) -> list[Mapping]:
    return list(sch.get("oneOf") or sch.get("anyOf") or [])


#: the longest value a message quotes [characters]: a 10 MB string is named by its length, not printed
_SHOW_MAX = 60


def _show(instance: Any) -> str:
    if instance is None:
        return "null"
    text = repr(instance)
    return text if len(text) <= _SHOW_MAX else f"{text[: _SHOW_MAX - 5]}...{text[-2:]}"


def _message(e: jsonschema.ValidationError) -> str:
    """One line for a schema violation: the key, what is wrong and what is valid."""
    v, sch = e.validator, e.schema
    if v == "required":
        name = e.message.split("'")[1] if "'" in e.message else e.message
        p = _property_schema(_ROOT.get("schema", {}), list(e.absolute_schema_path), name)
        what = "; ".join(
            x for x in (p.get("description", ""), f"valid {_range(p)}" if _range(p) else "") if x
        )
        return f"{name!r} is missing" + (f" ({what})" if what else "")
    desc = sch.get("description", "") if isinstance(sch, dict) else ""
    what = f" ({desc})" if desc else ""
    if v == "additionalProperties":
        unknown = sorted(set(e.instance) - set(sch.get("properties", {})))
        valid = ", ".join(sch.get("properties", {}))
        return f"unknown key{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))}: valid {valid}"
    if v in _BOUNDS:
        return f"{e.instance!r} is out of range: must be {_range(sch)}{what}"
    if v == "enum":
        return f"{_show(e.instance)} is not one of {', '.join(map(str, sch['enum']))}"
    if v == "type":
        types = [sch["type"]] if isinstance(sch["type"], str) else sch["type"]
        was = " or ".join(_TYPES.get(t, t) for t in types)
        return f"{_show(e.instance)} is not {was}: must be {_kind(sch)}{what}"
    if v == "minItems":
        return (
            f"{_show(e.instance)} has {len(e.instance)} item(s): must have at least {sch['minItems']}{what}"
        )
    if v == "maxLength":
        return f"{_show(e.instance)} has {len(e.instance)} characters: at most {sch['maxLength']}{what}"
    if v == "pattern":
        return f"{_show(e.instance)} does not match {sch['pattern']}{what}"
    if v == "maxItems":
        return f"{_show(e.instance)} has {len(e.instance)} items: must have at most {sch['maxItems']}{what}"
    if v in ("oneOf", "anyOf"):
        kinds = " or ".join(_kind(a) for a in _alternatives(sch))
        return f"{_show(e.instance)} is not valid: must be " + (
            (desc[:1].lower() + desc[1:]) if desc else kinds
        )
    return (
        e.message
        if len(e.message) <= 2 * _SHOW_MAX
        else f"{_show(e.instance)}: {e.validator} {e.validator_value}"
    )


def _path(e: jsonschema.ValidationError) -> list:
    return list(e.absolute_path)


def _locate(e: jsonschema.ValidationError) -> tuple[list, str]:
    """The key path and the message of a violation; for a ``oneOf``/``anyOf`` (a grid, a case
    reference, an amplitude) the violation of the alternative whose type the value has, so that the
    message names the key and what it must be (``maps.lambda_R.lambda.num: 0 is out of range: must be
    >= 1``) instead of "is not valid under any of the given schemas"."""
    if e.validator not in ("oneOf", "anyOf") or not e.context:
        return _path(e), _message(e)
    by_alt: dict[Any, list[jsonschema.ValidationError]] = {}
    for sub in e.context:
        by_alt.setdefault(sub.relative_schema_path[0], []).append(sub)
    fitting = [
        errs
        for errs in by_alt.values()
        if not any(x.validator == "type" and not x.relative_path for x in errs)
    ]
    if len(fitting) != 1:
        return _path(e), _message(e)
    sub = sorted(fitting[0], key=lambda x: [str(k) for k in x.absolute_path])[0]
    path, msg = _locate(sub)
    alts = _alternatives(e.schema)
    if not sub.relative_path and len(alts) > 1:  # the value itself: say what else it may be
        chosen = sub.relative_schema_path[0]
        others = [_kind(a) for k, a in enumerate(alts) if k != chosen]
        msg += "; or " + " or ".join(others)
    return path, msg


def _first_error(validator, config: dict) -> None:
    errors = sorted(validator.iter_errors(config), key=lambda e: [str(k) for k in e.absolute_path])
    if errors:
        path, msg = _locate(errors[0])
        where = ".".join(str(p) for p in path) or "(top level)"
        raise ConfigError(f"configuration: {where}: {msg}")


def validate_config(config: dict, schema_path: str | Path | None = None) -> dict:
    """Validate a workflow configuration in place, filling in the defaults of the schema.

    Parameters
    ----------
    config : dict
        Parsed YAML (changed in place).
    schema_path : path-like, optional
        The schema (default :func:`isorock.resources.config_schema`).

    Returns
    -------
    dict
        ``config``.

    Raises
    ------
    ConfigError
        The first violation, in one line naming the key.
    """
    path = Path(schema_path) if schema_path is not None else resources.config_schema()
    try:
        schema = yaml.safe_load(path.read_text())
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the configuration schema: {exc.strerror}") from None
    _ROOT["schema"] = schema
    check_string_lengths(config)
    check_finite_tree(config)
    validator = _defaulting_validator(schema)
    _first_error(validator, config)
    _first_error(validator, config)  # a second pass validates the defaults filled in by the first
    _check_names(config)
    check_values(config)
    _check_assessment(config)
    return config


#: the sections of the paper's studies (the keys that ask for them)
STUDY_KEYS = ("overturn", "maps", "pulses", "studies")


def studies_default(user: Mapping) -> dict:
    """``{"studies": []}`` when a user's configuration asks for an assessment and none of the paper's
    studies (no ``overturn``, ``maps``, ``pulses`` or ``studies`` key); else ``{}``. Merged over the
    defaults, so that a file with only ``records``, ``isolation`` and ``assessment`` is a complete
    assessment configuration."""
    if user.get("assessment") and not any(k in user for k in STUDY_KEYS):
        return {"studies": []}
    return {}


def apply_studies_default(config: dict, user_files: Sequence[str | Path]) -> dict:
    """:func:`studies_default` for a configuration Snakemake has merged: the keys of the user's
    ``--configfile`` files decide (the Snakefile calls this before :func:`validate_config`)."""
    user: dict = {}
    for f in user_files:
        try:
            merge_config(user, _read(f))
        except ConfigError:
            continue  # Snakemake has read it already; a bad file is reported by the validation
    if "studies" not in config or studies_default(user):
        merge_config(config, studies_default(user))
    return config


_BODY_KEYS = ("b_left_m", "b_right_m", "h_cg_m", "r_gyration_m")


def _check_body(o: Mapping, where: str) -> bool:
    """Check an object given as a rigid body (``b_left_m, b_right_m, h_cg_m, r_gyration_m`` or ``parts``);
    False for a uniform block (``height_m``/``width_m`` or ``lambda``/``R_m``)."""
    from isorock.assessment.stripes import AssessedObject

    geo = [k for k in _BODY_KEYS if k in o]
    block = [k for k in ("height_m", "width_m", "lambda", "R_m") if k in o]
    if not geo and "parts" not in o:
        if "restitution" in o or "polarity" in o:
            key = "restitution" if "restitution" in o else "polarity"
            raise ConfigError(f"{where} ({o['name']}): {key} is for a rigid body (b_left_m ... or parts)")
        return False
    given = (["parts"] if "parts" in o else []) + (["b_left_m ..."] if geo else [])
    if len(given) > 1 or block:
        raise ConfigError(
            f"{where} ({o['name']}): give one description of the object: height_m and width_m, lambda and "
            "R_m, b_left_m/b_right_m/h_cg_m/r_gyration_m, or parts"
        )
    if geo and len(geo) < 4:
        missing = ", ".join(k for k in _BODY_KEYS if k not in o)
        raise ConfigError(
            f"{where} ({o['name']}): a rigid body needs {', '.join(_BODY_KEYS)}: give {missing}"
        )
    try:
        obj = AssessedObject.from_config(o)
        obj.system(NoIsolation())
    except ParameterError as exc:
        raise ConfigError(f"{where} ({o['name']}): {exc}") from None
    if obj.slides and o.get("slide_allow_m") is None:
        raise ConfigError(
            f"{where} ({o['name']}): friction {o['friction']:g} is below tan(alpha) "
            f"{obj.block().tan_alpha:.3g} of its weaker side: the object slides and never rocks; give "
            "slide_allow_m, how far it may slide [m], which a slide beyond fails"
        )
    return True


def _check_assessment(cfg: Mapping) -> None:
    """What the schema cannot express for ``assessment``: an object's size given one way, case names,
    increasing stripes, a complete design grid."""
    a = cfg.get("assessment")
    if not a:
        return
    for k, o in enumerate(a["objects"]):
        where = f"configuration: assessment.objects.{k}"
        if _check_body(o, where):
            continue
        dims, lr = ("height_m" in o, "width_m" in o), ("lambda" in o, "R_m" in o)
        if any(dims) and any(lr):
            raise ConfigError(f"{where}: give height_m and width_m, or lambda and R_m, not both")
        if not (all(dims) or all(lr)):
            raise ConfigError(f"{where}: the size needs height_m and width_m (m), or lambda and R_m")
        try:
            check_object(o.get("height_m"), o.get("width_m"), o.get("friction"))
        except ParameterError as exc:
            raise ConfigError(f"{where} ({o['name']}): {exc}") from None
        lam = o["height_m"] / o["width_m"] if "height_m" in o else o["lambda"]
        if o["friction"] < 1.0 / lam and o.get("slide_allow_m") is None:
            raise ConfigError(
                f"{where} ({o['name']}): friction {o['friction']:g} is below tan(alpha) {1.0 / lam:.3g}: the "
                "object slides and never rocks; give slide_allow_m, how far it may slide [m] (to its "
                "plinth's edge or a neighbour), which a slide beyond fails"
            )
    names = [o["name"] for o in a["objects"]]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ConfigError(f"configuration: assessment.objects: name {dup[0]!r} is used twice")
    known = [c["name"] for c in cfg["isolation"]["cases"]]
    for c in a["cases"]:
        if c not in known:
            raise ConfigError(
                f"configuration: assessment.cases: unknown isolation case {c!r}: valid {', '.join(known)}"
            )
    st = list(a["stripes_g"])
    if any(b <= x for x, b in zip(st, st[1:], strict=False)):
        raise ConfigError("configuration: assessment.stripes_g: the stripe levels must increase")
    _check_level_range(a)
    _check_levels(a, st)
    _check_grid(a)


#: the highest level of a stripe, design or MCE level in each unit of a measure (the schema's maximum
#: is the larger, for PGV): 10 g, 1000 cm/s
_LEVEL_MAX = {"g": 10.0, "cm/s": 1000.0}


def _check_level_range(a: Mapping) -> None:
    """Every level given in the unit of ``assessment.imt`` within its range (:data:`_LEVEL_MAX`)."""
    from isorock.errors import ParameterError
    from isorock.processing.imt import parse_imt

    try:
        imt = parse_imt(a.get("imt") or a.get("measure") or "PGA", "assessment.imt")
    except ParameterError as exc:
        raise ConfigError(f"configuration: {exc}") from None
    top = _LEVEL_MAX[imt.unit]
    for key in ("stripes_g", "design_g", "mce_g"):
        v = a.get(key)
        vals = [] if v is None else (v if isinstance(v, list) else [v])
        over = [x for x in vals if x > top]
        if over:
            raise ConfigError(
                f"configuration: assessment.{key}: {over[0]:g} {imt.unit} is beyond {top:g} {imt.unit}, the "
                f"range of {imt} (assessment.imt)"
            )


def _check_grid(a: Mapping) -> None:
    """A design grid with the axes of its kind, design levels to rank at, bounds low < high, and FP
    friction coefficients of real isolators."""
    grid = a.get("design_grid")
    if not grid:
        return
    need = ("Tb_s", "xi_b") if grid["kind"] == "linear" else ("mu_b", "R_b_m")
    other = ("mu_b", "R_b_m") if grid["kind"] == "linear" else ("Tb_s", "xi_b")
    missing = [k for k in need if k not in grid]
    if missing:
        raise ConfigError(
            f"configuration: assessment.design_grid: a {grid['kind']} grid needs {' and '.join(need)} "
            f"(missing {', '.join(missing)})"
        )
    extra = [k for k in other if k in grid]
    if extra:
        raise ConfigError(
            f"configuration: assessment.design_grid: {', '.join(extra)} do not apply to a {grid['kind']} grid"
        )
    for key in need:
        spec = grid[key]
        twice = (
            int(spec["num"]) > 1 and float(spec["start"]) == float(spec["stop"])
            if isinstance(spec, Mapping)
            else len({float(v) for v in spec}) != len(spec)
        )  # without making a grid of any size
        if twice:
            shown = dict(spec) if isinstance(spec, Mapping) else list(spec)
            raise ConfigError(f"configuration: assessment.design_grid.{key}: {shown}: a value is given twice")
        b = (grid.get("bounds") or {}).get(key)
        if b is not None and not b[0] < b[1]:
            raise ConfigError(
                f"configuration: assessment.design_grid.bounds.{key}: {b}: give [low, high], low < high"
            )
        check_grid_values(f"assessment.design_grid.{key}", spec, DESIGN_AXES[key])
        if b is not None:
            for v in b:
                refuse(f"assessment.design_grid.bounds.{key}", DESIGN_AXES[key], key, v)


def _check_levels(a: Mapping, st: list) -> None:
    """Design levels given one way and within the stripes, MCE levels one per design level, return
    periods with a hazard curve that reads and covers them."""
    hz = a.get("hazard")
    if hz:
        given = [k for k in ("openquake", "usgs", "file", "points") if hz.get(k) is not None]
        if len(given) != 1:
            raise ConfigError(
                "configuration: assessment.hazard: give exactly one of openquake, usgs, file or points"
                + (f" (given: {', '.join(given)})" if given else "")
            )
    from isorock.assessment.hazard_files import curve_from_config
    from isorock.assessment.scaling import scaling_from_config

    scaling_from_config(a, curve_from_config(hz, Path.cwd()) if hz else None)
    for g_key, t_key in (("design_g", "design_return_period_yr"), ("mce_g", "mce_return_period_yr")):
        if a.get(t_key) and a.get(g_key):
            raise ConfigError(f"configuration: assessment: give {g_key} or {t_key}, not both")
        if a.get(t_key) and not hz:
            raise ConfigError(
                f"configuration: assessment.{t_key}: a return period is read off the site's hazard curve: "
                "add assessment.hazard (openquake, usgs, file or points), or give the level in g"
            )
    if not (a.get("design_g") or a.get("design_return_period_yr")):
        raise ConfigError(
            "configuration: assessment names no design level (design_g is empty): give design_g (g), or "
            "design_return_period_yr with a hazard curve; the advice judges the object there"
        )
    from isorock.assessment.levels import resolve_levels
    from isorock.assessment.target import Target

    Target.from_config(a.get("target"), bool(hz))
    lv = resolve_levels(a, Path.cwd())
    key = "design_return_period_yr" if a.get("design_return_period_yr") else "design_g"
    out = [x for x in lv.design if not st[0] <= x <= st[-1]]
    u = "cm/s" if str(a.get("imt") or "").upper() == "PGV" else "g"
    if out:
        raise ConfigError(
            f"configuration: assessment.{key}: {out[0]:g} {u} is outside the stripes ({st[0]:g} to "
            f"{st[-1]:g} {u}): a fragility is not extrapolated; add a stripe at or beyond it"
        )
    n = len(lv.design)
    for k in ("mce_g", "mce_return_period_yr"):
        v = a.get(k)
        if isinstance(v, list) and len(v) not in (n, 1 if k == "mce_return_period_yr" else n):
            raise ConfigError(
                f"configuration: assessment.{k}: {len(v)} values for {n} design levels (give one for all, "
                "or one per design level)"
            )


def merge_config(base: dict, overlay: Mapping) -> dict:
    """Merge ``overlay`` into ``base`` in place as Snakemake merges ``--configfile`` over ``configfile:``:
    mappings key by key, every other value (lists included) replaced."""
    for key, value in overlay.items():
        if isinstance(value, Mapping) and isinstance(base.get(key), dict):
            merge_config(base[key], value)
        else:
            base[key] = copy.deepcopy(value)
    return base


class _DuplicateKey(yaml.YAMLError):
    """A mapping of the YAML file gives a key twice (``safe_load`` would keep the last, silently)."""


class _UniqueKeyLoader(yaml.SafeLoader):
    """``yaml.SafeLoader`` that refuses a key given twice in one mapping."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict:
        seen: set = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)  # type: ignore[no-untyped-call]
            if key in seen:
                raise _DuplicateKey(
                    f"line {key_node.start_mark.line + 1}: the key {key!r} is given twice (the last one "
                    "would win silently): keep one"
                )
            seen.add(key)
        return super().construct_mapping(node, deep=deep)


def _read(source: str | Path | Mapping) -> dict:
    if isinstance(source, Mapping):
        return copy.deepcopy(dict(source))
    p = Path(source)
    try:
        cfg = yaml.load(p.read_text(), Loader=_UniqueKeyLoader) or {}  # noqa: S506 (a SafeLoader)
    except OSError as exc:
        raise ConfigError(f"{p}: cannot read configuration: {exc.strerror or exc}") from None
    except _DuplicateKey as exc:
        raise ConfigError(f"{p}:{exc}") from None
    except yaml.YAMLError as exc:
        raise ConfigError(f"{p}: not valid YAML: {str(exc).splitlines()[0]}") from None
    if not isinstance(cfg, dict):
        raise ConfigError(f"{p}: a configuration is a mapping of keys, got {type(cfg).__name__}")
    return cfg


def load_config(*sources: str | Path | Mapping) -> dict:
    """Read, merge (later sources over earlier ones) and validate configurations; defaults filled in.

    Parameters
    ----------
    *sources : path-like or mapping
        YAML files or parsed configurations; none gives the schema defaults.

    Raises
    ------
    ConfigError
        Unreadable file, bad YAML or a violation (one line).
    """
    cfg: dict = {}
    for s in sources:
        merge_config(cfg, _read(s))
    return validate_config(cfg)


def user_assessment(files: Sequence[str | Path]) -> dict | None:
    """The ``assessment`` section of the user's configuration files (merged as Snakemake merges them),
    or None: it replaces config/config.yaml's example assessment, which only the default run has (the
    Snakefile and :func:`workflow_config` apply the same rule)."""
    user: dict = {}
    for f in files:
        try:
            merge_config(user, _read(f))
        except ConfigError:
            continue  # Snakemake has read it already; a bad file is reported by the validation
    return user.get("assessment")


def workflow_config(configfile: str | Path | Mapping | None = None, overrides: Mapping | None = None) -> dict:
    """The configuration a workflow run uses: ``config/config.yaml`` (the Snakefile's ``configfile:``)
    with ``configfile`` merged over it, as ``snakemake --configfile`` does, then ``overrides`` (as
    ``snakemake --config KEY=VALUE``); validated."""
    default = resources.default_config()
    base = _read(default)
    if configfile is not None and (
        isinstance(configfile, Mapping) or Path(configfile).resolve() != Path(default).resolve()
    ):
        base.pop("assessment", None)  # the example assessment is the default run's (user_assessment)
    sources: list[str | Path | Mapping] = [base]
    if configfile is not None:
        user = _read(configfile)
        sources += [studies_default(user), user]
    if overrides:
        sources.append(overrides)
    return load_config(*sources)


def _check_names(cfg: Mapping) -> None:
    """Cross-checks the schema cannot express: case names exist and are unique (the names of the
    studies that do not run are not checked: an assessment brings its own cases)."""
    names = [c["name"] for c in cfg["isolation"]["cases"]]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ConfigError(f"configuration: isolation.cases: name {dup[0]!r} is used twice")
    for k, c in enumerate(cfg["isolation"]["cases"]):
        try:
            bounded = {key: c.get(key) for key in ("Tb_s", "xi_b", "rho", "R_b_m")}
            check_isolator(c["kind"], c.get("mu_b"), **bounded)
        except ParameterError as exc:
            raise ConfigError(f"configuration: isolation.cases.{k} ({c['name']}): {exc}") from None
    known = set(names)

    def need(name: str, where: str) -> None:
        if name not in known:
            raise ConfigError(
                f"configuration: {where}: unknown isolation case {name!r}: valid {', '.join(names)}"
            )

    studies = set(cfg.get("studies", ("overturn", "maps", "pulses")))
    if "overturn" in studies:
        for ref in cfg["overturn"]["cases"]:
            need(ref_name(ref), "overturn.cases")
    if "maps" in studies:
        for ref in cfg["maps"]["lambda_R"]["cases"]:
            need(ref_name(ref), "maps.lambda_R.cases")
    if "pulses" not in studies:
        return
    p = cfg["pulses"]
    for shape, cases in p["shapes"].items():
        for c in cases:
            need(c, f"pulses.shapes.{shape}")
    for c in p["maps"]["cases"]:
        need(c, "pulses.maps.cases")
    base = p["vs_isolation"]["base_case"]
    need(base, "pulses.vs_isolation.base_case")
    kind = {c["name"]: c["kind"] for c in cfg["isolation"]["cases"]}[base]
    if kind != "linear" and p["vs_isolation"]["shapes"]:
        raise ConfigError(
            f"configuration: pulses.vs_isolation.base_case: {base!r} is a {kind!r} case; it must be linear"
        )


def ref_name(ref: str | Mapping) -> str:
    """Case name of a case reference (a name, or ``{case, records}``)."""
    return ref if isinstance(ref, str) else ref["case"]


def ref_applies(ref: str | Mapping, record_id: str) -> bool:
    """Whether a case reference applies to a record (``records`` empty or naming it)."""
    if isinstance(ref, str):
        return True
    recs = ref.get("records") or []
    return not recs or record_id in recs


@dataclass(frozen=True)
class IsolationCase:
    """A named isolation case of the configuration.

    Parameters
    ----------
    name : str
        Name used in the configuration, the tables and the map names.
    kind : {"none", "linear", "fp"}
        Isolation model.
    rho : float
        Block-to-base mass ratio [-] (ignored for ``none``).
    Tb_s : float or None
        Linear isolator period [s].
    xi_b : float or None
        Linear isolator damping ratio [-].
    mu_b : float or None
        FP friction coefficient [-].
    R_b_m : float or None
        FP radius of curvature [m].
    Y_m, bw_beta, bw_gamma : float or None
        Bouc-Wen parameters of the FP isolator ([m], [-], [-]); None: the model's defaults.
    """

    name: str
    kind: str
    rho: float = 0.5
    Tb_s: float | None = None
    xi_b: float | None = None
    mu_b: float | None = None
    R_b_m: float | None = None
    Y_m: float | None = None
    bw_beta: float | None = None
    bw_gamma: float | None = None

    def isolation(self) -> Isolation:
        """The :mod:`isorock.physics.model` isolation object
        (:func:`isorock.physics.model.make_isolation`)."""
        params = {k: v for k, v in asdict(self).items() if k not in ("name", "kind")}
        return make_isolation(self.kind, **params)

    def columns(self) -> dict[str, Any]:
        """The case columns of the tables: case, isolation, Tb_s, xi_b, rho, mu_b, R_b_m (NaN if n/a)."""
        nan = math.nan
        iso = self.isolation()
        return {
            "case": self.name,
            "isolation": self.kind,
            "Tb_s": float(iso.Tb) if self.kind != "none" else nan,
            "xi_b": float(self.xi_b) if self.kind == "linear" else nan,
            "rho": float(self.rho) if self.kind != "none" else nan,
            "mu_b": float(self.mu_b) if self.kind == "fp" else nan,
            "R_b_m": float(self.R_b_m) if self.kind == "fp" else nan,
        }


def isolation_cases(config: Mapping) -> dict[str, IsolationCase]:
    """The isolation cases of a validated configuration, by name."""
    rho = float(config["isolation"]["rho"])
    out = {}
    for c in config["isolation"]["cases"]:
        kw = {k: c[k] for k in ("Tb_s", "xi_b", "mu_b", "R_b_m", "Y_m", "bw_beta", "bw_gamma") if k in c}
        out[c["name"]] = IsolationCase(name=c["name"], kind=c["kind"], rho=float(c.get("rho", rho)), **kw)
    return out


def case_dict(case: IsolationCase) -> dict:
    """JSON-ready form of a case (Snakemake params): its fields that are set."""
    return {k: v for k, v in asdict(case).items() if v is not None}


def case_from(d: Mapping) -> IsolationCase:
    """The case of a :func:`case_dict`."""
    return IsolationCase(**d)
