"""The ``--help`` of every command and sub-command: each option explained, nothing hidden shown as
``==SUPPRESS==``, no mention of an option the command does not take, units on the numbers, and the
deprecated spellings marked and still working (``--amp-max``, the old name of ``--pga-max``)."""

from __future__ import annotations

import argparse
import json
import re

import pytest

from isorock.cli import build_parser, main
from isorock.cli.options import DeprecatedAlias, RefusedOption

#: sub-commands hidden on purpose (added without help=): old names that still work
HIDDEN_COMMANDS = {("isorock", "records", "import")}
#: options hidden on purpose (help=argparse.SUPPRESS), by command and first option string: the old
#: name --config of --processing, and --pga/--amp refused where only --pga-max exists (an exact match,
#: so that argparse does not read --pga as an abbreviation of --pga-max)
HIDDEN_OPTIONS = {
    ("isorock info", "--config"),
    ("isorock pulse", "--config"),
    ("isorock min-overturn", "--pga"),
    ("isorock demo", "--pga"),
}
OPTION = re.compile(r"(?<![\w-])--[A-Za-z][\w-]*")
UNIT = re.compile(r"\[[^\]]+\]")  # [m], [s], [g], [-], [deg clockwise from north] ...


def _walk(parser: argparse.ArgumentParser, path: tuple[str, ...] = ("isorock",)):
    """``(path, parser)`` of ``parser`` and of every sub-command below it, at any depth."""
    yield path, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _walk(sub, (*path, name))


PARSERS = list(_walk(build_parser()))


def _named(word: str, text: str) -> bool:
    """Whether ``text`` has ``word`` as a word of its own (``--pga`` is not in ``--pga-max``)."""
    return re.search(rf"(?<![\w-]){re.escape(word)}(?![\w-])", text) is not None


def _accepted(parser: argparse.ArgumentParser) -> set[str]:
    """The option strings ``parser`` takes (hidden ones included, refused ones not)."""
    return {s for a in parser._actions if not isinstance(a, RefusedOption) for s in a.option_strings}


def _mentions(text: str | None) -> set[str]:
    return set() if not text else {m.rstrip("-") for m in OPTION.findall(text)}


def test_the_walk_reaches_every_level():
    paths = {" ".join(p) for p, _ in PARSERS}
    assert {"isorock simulate", "isorock records add", "isorock map lambda-R", "isorock assess"} <= paths
    assert "isorock records import" in paths  # hidden, but there
    assert len(paths) >= 16


@pytest.fixture(autouse=True)
def _columns(monkeypatch):
    monkeypatch.setenv("COLUMNS", "110")  # the width of the help, as on a terminal


@pytest.mark.parametrize("path, parser", PARSERS, ids=[" ".join(p) for p, _ in PARSERS])
def test_every_argument_has_a_help(path, parser):
    text = parser.format_help()
    assert "==SUPPRESS==" not in text and "==SUPPRESS==" not in parser.format_usage()
    for action in parser._actions:
        name = action.option_strings[0] if action.option_strings else action.metavar or action.dest
        if action.help == argparse.SUPPRESS:
            assert (parser.prog, name) in HIDDEN_OPTIONS, f"{parser.prog} {name}: hidden, not on purpose"
            for s in action.option_strings:
                assert not _named(s, text), f"{parser.prog}: the hidden {s} shows in --help"
            continue
        assert isinstance(action.help, str) and action.help.strip(), f"{parser.prog} {name}: no help"
        if action.type is float:
            assert UNIT.search(action.help), f"{parser.prog} {name}: a number without its [unit]"
        if isinstance(action, DeprecatedAlias):
            for old in set(action.option_strings) & set(DeprecatedAlias.deprecated):
                assert f"{old} is its deprecated alias" in action.help, f"{parser.prog} {old}"


@pytest.mark.parametrize("path, parser", PARSERS, ids=[" ".join(p) for p, _ in PARSERS])
def test_every_subcommand_is_listed_with_a_help_or_hidden(path, parser):
    text = parser.format_help()
    for action in parser._actions:
        if not isinstance(action, argparse._SubParsersAction):
            continue
        listed = {c.dest: c.help for c in action._choices_actions}
        for name in action.choices:
            if (*path, name) in HIDDEN_COMMANDS:
                assert name not in listed and not _named(name, text), f"{parser.prog}: {name} shows"
            else:
                help_ = listed.get(name)
                assert help_ and help_ != argparse.SUPPRESS and help_.strip(), f"{parser.prog} {name}"


@pytest.mark.parametrize("path, parser", PARSERS, ids=[" ".join(p) for p, _ in PARSERS])
def test_helps_name_only_options_the_command_takes(path, parser):
    own = [parser.description, parser.epilog]
    own += [a.help for a in parser._actions if a.help != argparse.SUPPRESS]
    for text in own:
        wrong = _mentions(text) - _accepted(parser)
        assert not wrong, f"{parser.prog} --help names {sorted(wrong)}, which it does not take: {text!r}"
    for action in parser._actions:  # a sub-command's line in the list names the sub-command's options
        if isinstance(action, argparse._SubParsersAction):
            for c in action._choices_actions:
                wrong = _mentions(c.help) - _accepted(action.choices[c.dest])
                assert not wrong, f"{parser.prog} {c.dest}: its help names {sorted(wrong)}"


def test_records_import_is_hidden_but_works():
    parser = build_parser()
    args = parser.parse_args(["records", "import", "--json"])
    assert args.deprecated_name == "import" and args.func.__name__ == "_cmd_status"
    assert args.func is parser.parse_args(["records", "status"]).func


@pytest.mark.parametrize("command", ["min-overturn", "demo"])
def test_amp_max_is_a_deprecated_alias_of_pga_max(capsys, command):
    parser = build_parser()
    block = (
        ["--lambda", "4", "--R", "3", "--pulse", "rect", "--td", "0.5"] if command == "min-overturn" else []
    )
    new = parser.parse_args([command, *block, "--pga-max", "2.5"])
    assert capsys.readouterr().err == ""
    old = parser.parse_args([command, *block, "--amp-max", "2.5"])
    assert old.pga_max == new.pga_max == 2.5 and not hasattr(old, "amp_max")
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--amp-max is deprecated" in err and "use --pga-max" in err


def test_amp_max_runs_as_pga_max_and_warns(capsys):
    argv = ["min-overturn", "--lambda", "4", "--R", "3", "--pulse", "rect", "--td", "0.5", "--json"]
    assert main([*argv, "--pga-max", "0.3"]) == 0
    cap = capsys.readouterr()
    new = json.loads(cap.out)
    # in a fresh checkout the first fixed-base analysis of this process compiles the engine and says so
    err = [line for line in cap.err.splitlines() if not line.startswith("isorock: compiling the engine")]
    assert err == []
    assert main([*argv, "--amp-max", "0.3"]) == 0
    cap = capsys.readouterr()
    old = json.loads(cap.out)
    assert "--amp-max is deprecated" in cap.err and "use --pga-max" in cap.err
    new.pop("seconds"), old.pop("seconds")
    assert old == new and new["min_overturn_g"] is None  # nothing overturns up to 0.3 g


@pytest.mark.parametrize("command", ["min-overturn", "demo"])
@pytest.mark.parametrize("flag", ["--pga", "--amp"])
def test_pga_is_not_read_as_pga_max(capsys, command, flag):
    """``--pga`` would otherwise be an abbreviation of ``--pga-max`` (and ``--amp`` of ``--amp-max``)."""
    block = (
        ["--lambda", "4", "--R", "3", "--pulse", "rect", "--td", "0.5"] if command == "min-overturn" else []
    )
    with pytest.raises(SystemExit) as exc:  # a usage error
        main([command, *block, flag, "0.5"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert f"error: {flag} does not apply to isorock {command}" in err and "--pga-max" in err
