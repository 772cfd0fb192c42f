"""Processing configurations: an ordered list of named steps read from YAML, and :func:`process`,
which applies them to a copy of a record."""

from __future__ import annotations

import inspect
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from obspy import Stream, Trace

from isorock.errors import IsorockError
from isorock.processing.qa import ensure_qa
from isorock.processing.steps import STEPS, as_float

__all__ = [
    "DEFAULT_CONFIG_NAME",
    "ProcessingStep",
    "ProcessingConfig",
    "load_config",
    "default_config",
    "process",
]

DEFAULT_CONFIG_NAME = "processing.yaml"
"""The default configuration, shipped in this package."""


@dataclass(frozen=True)
class ProcessingStep:
    """One named step with its keyword parameters.

    Parameters
    ----------
    name : str
        A key of :data:`STEPS`.
    params : dict
        Keyword parameters of the step function (units as documented there).
    """

    name: str
    params: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.name not in STEPS:
            raise IsorockError(f"processing step {self.name!r} is unknown: valid {', '.join(STEPS)}")
        if not isinstance(self.params, Mapping):
            raise IsorockError(
                f"processing step {self.name!r}: parameters must be a mapping, got "
                f"{type(self.params).__name__}"
            )
        sig = inspect.signature(STEPS[self.name])
        valid = [p for p in sig.parameters if p != "tr"]
        bad = [k for k in self.params if k not in valid]
        if bad:
            raise IsorockError(
                f"processing step {self.name!r}: unknown parameter(s) {', '.join(bad)}: "
                f"valid {', '.join(valid)}"
            )
        object.__setattr__(self, "params", dict(self.params))

    def __call__(self, tr: Trace) -> Trace:
        return STEPS[self.name](tr, **self.params)


@dataclass(frozen=True)
class ProcessingConfig:
    """An ordered list of processing steps.

    Parameters
    ----------
    steps : tuple of ProcessingStep
        Applied in order.
    """

    steps: tuple[ProcessingStep, ...]

    @classmethod
    def from_obj(cls, obj: object, source: str = "configuration") -> ProcessingConfig:
        """Build from parsed YAML: ``{"processing": [...]}`` or the list itself.

        Each list item is ``{name: {param: value}}`` (or ``{name: null}``, or a bare name).
        """
        if isinstance(obj, ProcessingConfig):
            return obj
        if isinstance(obj, Mapping):
            if "processing" not in obj:
                raise IsorockError(f"{source}: no 'processing' list")
            obj = obj["processing"]
        if not isinstance(obj, Iterable) or isinstance(obj, (str, bytes)):
            raise IsorockError(f"{source}: 'processing' must be a list of steps")
        steps = []
        for i, item in enumerate(obj, start=1):
            if isinstance(item, ProcessingStep):
                steps.append(item)
                continue
            if isinstance(item, str):
                name, params = item, {}
            elif isinstance(item, Mapping) and len(item) == 1:
                ((name, params),) = item.items()
                params = params or {}
            else:
                raise IsorockError(
                    f"{source}: step {i} must be a name or a one-key mapping {{name: {{params}}}}"
                )
            try:
                steps.append(ProcessingStep(str(name), params))
            except IsorockError as exc:
                raise IsorockError(f"{source}: step {i}: {exc}") from None
        return cls(tuple(steps))

    def with_step(self, name: str, **params: Any) -> ProcessingConfig:
        """A copy where the parameters of every step ``name`` are updated (the step is appended if absent)."""
        steps = list(self.steps)
        found = False
        for i, s in enumerate(steps):
            if s.name == name:
                steps[i] = ProcessingStep(name, {**s.params, **params})
                found = True
        if not found:
            steps.append(ProcessingStep(name, params))
        return ProcessingConfig(tuple(steps))

    def to_obj(self) -> dict:
        """The YAML-ready form ``{"processing": [{name: params}, ...]}``."""
        return {"processing": [{s.name: dict(s.params)} for s in self.steps]}


#: the largest processing file read [bytes] (the packaged one is under 2 kB)
MAX_FILE_BYTES = 1_000_000
#: what a processing file is, for the messages that refuse another file
WHAT_IT_MUST_BE = (
    "a processing file is YAML text with a 'processing' list of steps, e.g. 'processing: [{detrend: {type: "
    "linear}}]' (isorock's own: isorock/processing/processing.yaml)"
)


def load_config(path: str | Path) -> ProcessingConfig:
    """Read a processing configuration from a YAML file.

    Parameters
    ----------
    path : path-like
        A YAML file: a mapping with a ``processing`` list of steps (or the list itself).

    Raises
    ------
    IsorockError
        One line naming the file and what a processing file must be: it cannot be read, is not a
        regular file, is larger than :data:`MAX_FILE_BYTES`, binary, not YAML, has no ``processing``
        list (``/etc/passwd``, a workflow configuration), or a step is unknown or malformed.
    """
    path = Path(path)

    def refuse(why: str) -> IsorockError:
        return IsorockError(f"{path}: not a processing file ({why}): {WHAT_IT_MUST_BE}")

    try:
        if path.exists() and not path.is_file():
            raise refuse("not a regular file")
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise refuse(f"{size:,} bytes")
        raw = path.read_bytes()
    except OSError as exc:
        raise IsorockError(f"{path}: cannot read processing configuration: {exc.strerror or exc}") from None
    if b"\0" in raw:
        raise refuse("binary")
    try:
        obj = yaml.safe_load(raw.decode("utf-8"))
    except UnicodeDecodeError:
        raise refuse("not UTF-8 text") from None
    except yaml.YAMLError as exc:
        raise refuse(f"not valid YAML: {str(exc).splitlines()[0]}") from None
    if not (isinstance(obj, Mapping) and "processing" in obj) and not isinstance(obj, list):
        raise refuse("empty" if obj is None else "no 'processing' list")
    if isinstance(obj, Mapping) and not isinstance(obj["processing"], list):
        raise refuse("'processing' is not a list of steps")
    bad = _non_finite(obj)
    if bad:
        raise IsorockError(
            f"{path}: {bad} is not a finite number: a step's setting must be a finite number (a NaN "
            "threshold would switch its check off)"
        )
    return ProcessingConfig.from_obj(obj, source=str(path))


def _non_finite(node: object, path: str = "") -> str | None:
    """The key path of the first number of ``node`` that is not finite (YAML ``.nan``, ``.inf``), or None."""
    import math

    if isinstance(node, dict):
        items: list[tuple[str, object]] = [(str(k), v) for k, v in node.items()]
    elif isinstance(node, list):
        items = [(str(k), v) for k, v in enumerate(node)]
    elif isinstance(node, float) and not math.isfinite(node):
        return path or "(top level)"
    else:
        return None
    for k, v in items:
        found = _non_finite(v, f"{path}.{k}" if path else k)
        if found:
            return found
    return None


def default_config() -> ProcessingConfig:
    """The configuration shipped as ``isorock/processing/processing.yaml``."""
    text = resources.files("isorock.processing").joinpath(DEFAULT_CONFIG_NAME).read_text()
    return ProcessingConfig.from_obj(yaml.safe_load(text), source=DEFAULT_CONFIG_NAME)


def _config(config: object) -> ProcessingConfig:
    if config is None:
        return default_config()
    if isinstance(config, (str, Path)):
        return load_config(config)
    return ProcessingConfig.from_obj(config)


def with_lowest_usable_frequency(config: object, luf_hz: float | None) -> object:
    """The processing of a record whose lowest usable frequency is ``luf_hz`` [Hz].

    Its ``bandpass_filter`` steps get ``luf_hz``: their high-pass corner ``freqmin`` is raised to it
    when it is higher, and the history of the record says so (:func:`isorock.processing.bandpass_filter`).
    ``config`` is returned unchanged when ``luf_hz`` is None or the processing has no
    ``bandpass_filter`` step.

    Parameters
    ----------
    config : ProcessingConfig, mapping, list, path or None
        As :func:`process` takes it (None: the packaged default).
    luf_hz : float or None
        The record's lowest usable frequency [Hz] (PEER's ``Lowest Useable Frequency``).
    """
    if luf_hz is None:
        return config
    cfg = _config(config)
    if not any(s.name == "bandpass_filter" for s in cfg.steps):
        return config
    return cfg.with_step("bandpass_filter", luf_hz=float(luf_hz))


def process(
    record: Trace | Stream, config: ProcessingConfig | Mapping | list | str | Path | None = None
) -> Trace | Stream:
    """Apply the processing steps to a copy of a trace or of every trace of a stream.

    Parameters
    ----------
    record : obspy.Trace or obspy.Stream
        Ground acceleration [m/s^2]; not changed.
    config : ProcessingConfig, mapping, list, path or None
        The steps: a :class:`ProcessingConfig`, parsed YAML (``{"processing": [...]}``
        or the list), a YAML file, or None for the packaged default.

    Returns
    -------
    obspy.Trace or obspy.Stream
        The processed copy (same type as ``record``), with the history in
        ``stats.processing`` and the QA marks in ``stats.qa`` (see :func:`qa_passed`).
    """
    cfg = _config(config)
    if isinstance(record, Stream):
        return Stream([_process_trace(tr, cfg) for tr in record])
    if not isinstance(record, Trace):
        raise IsorockError(f"process needs an obspy Trace or Stream, got {type(record).__name__}")
    return _process_trace(record, cfg)


#: the fewest samples a record may have to be processed: its filter, taper and baseline fit need more
#: than a handful (a real accelerogram has thousands)
MIN_SAMPLES = 8


def _process_trace(tr: Trace, cfg: ProcessingConfig) -> Trace:
    out = tr.copy()
    as_float(out)
    if out.stats.npts < MIN_SAMPLES:
        name = out.id.strip(".") or "(unnamed)"
        raise IsorockError(
            f"record {name} has {out.stats.npts} samples: too short to process (a record needs at least "
            f"{MIN_SAMPLES})"
        )
    if not np.all(np.isfinite(out.data)):
        raise IsorockError(f"record {out.id or '(unnamed)'} has non-finite samples")
    ensure_qa(out)
    for step in cfg.steps:
        step(out)
    return out
