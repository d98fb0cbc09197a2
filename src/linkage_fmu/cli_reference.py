"""The command-line reference (Markdown), written from the parser of :mod:`linkage_fmu.cli`,
so that it lists every command and option the command line has, with its help.

``python -m linkage_fmu.cli_reference > docs/cli.md`` writes the documentation's page (a
test keeps it current).

Examples
--------
>>> text = markdown()
>>> text.splitlines()[2]
'# Command-line reference'
>>> "## `linkage-fmu table`" in text and "| `--theta THETA` |" in text
True
"""

from __future__ import annotations

import argparse
import sys

from .cli import LOAD_COMMANDS, Parser, build_parser, subcommands

INTRO = """\
<!-- written by python -m linkage_fmu.cli_reference > docs/cli.md; do not edit -->

# Command-line reference

`linkage-fmu COMMAND LINKAGE [options]`, installed with the package (activate the venv,
`. .venv/bin/activate`, or call `.venv/bin/linkage-fmu`; `python -m linkage_fmu` is the
same). `LINKAGE` is a description file (`.toml`) or a preset's name. Each load of the
linkage is an option `--NAME VALUE` of {load_commands}, listed by
`linkage-fmu COMMAND LINKAGE --help` (a preset's one load is `--load`). Values may carry
units and be expressions, as in a description file:
`--set l_AB=120mm`, `--omega "1800 rpm"`, `--theta "0:360:15 deg"`; plain numbers are
SI, angles in radians. A user error ends with status 2 and one line naming the option
and what is wrong.
"""


def _cell(text: str) -> str:
    """``text`` as one cell of a Markdown table: one line, its bars escaped."""
    return " ".join(text.split()).replace("|", "\\|")


def _metavar(action: argparse.Action) -> str:
    """What an argument's value is called, as ``--help`` shows it: ``THETA``, ``KIND
    [NAME ...]``, ``NAME=VALUE``."""
    name = action.metavar
    if name is None and action.choices:
        name = "{" + ",".join(map(str, action.choices)) + "}"
    elif name is None:
        name = action.dest.upper() if action.option_strings else action.dest
    if isinstance(name, tuple):  # one name per value, the last repeated
        return " ".join([*name[:-1], f"[{name[-1]} ...]"] if action.nargs == "+"
                        else name)
    if action.nargs == "+":
        return f"{name} [{name} ...]"
    if action.nargs == "*":
        return f"[{name} ...]"
    if action.nargs == "?":
        return f"[{name}]"
    if isinstance(action.nargs, int):
        return " ".join([name] * action.nargs)
    return name


def _invocation(action: argparse.Action) -> str:
    """How an argument is typed: ``--theta THETA``, ``-o, --output OUTPUT``, ``linkage``."""
    if not action.option_strings:
        return _metavar(action)
    if action.nargs == 0:
        return ", ".join(action.option_strings)
    return ", ".join(action.option_strings) + " " + _metavar(action)


def _arguments(parser: Parser) -> list[str]:
    """The table of ``parser``'s arguments: how each is typed, its choices and default,
    its help."""
    rows = ["| argument | choices | default | meaning |", "|---|---|---|---|"]
    for action in parser.arguments:
        if action.dest in ("help", "version"):
            continue
        choices = ", ".join(f"`{c}`" for c in action.choices) if action.choices else ""
        default = ("" if action.default in (None, False, [], argparse.SUPPRESS)
                   or action.nargs == 0 else f"`{action.default}`")
        required = " (required)" if action.required and action.option_strings else ""
        rows.append(f"| `{_cell(_invocation(action))}`{required} | "
                    f"{_cell(choices)} | {_cell(default)} | {_cell(action.help or '')} |")
    return rows


def _usage(parser: Parser) -> str:
    return " ".join(parser.format_usage().removeprefix("usage: ").split())


def markdown(parser: Parser | None = None) -> str:
    """The reference of the command line ``parser`` (default: ``linkage-fmu``'s) in
    Markdown: its usage and examples, then each command with its summary, usage and a
    table of its arguments.

    Parameters
    ----------
    parser : linkage_fmu.cli.Parser, optional
        A parser with commands; default :func:`linkage_fmu.cli.build_parser`'s.

    Returns
    -------
    str
        The page, ending with a newline.

    Examples
    --------
    >>> "| `--Cs VALUE` (required) |" in markdown()
    True
    """
    parser = build_parser() if parser is None else parser
    commands = subcommands(parser)
    helps = {name: command.summary for name, command in commands.items()}
    loaded = [f"`{c}`" for c in LOAD_COMMANDS]
    intro = INTRO.format(load_commands=", ".join(loaded[:-1]) + " and " + loaded[-1])
    out = [intro, "```text", _usage(parser), "```", "", parser.description or "", "",
           "| command | what it does |", "|---|---|"]
    out += [f"| [`{name}`](#linkage-fmu-{name}) | {_cell(helps.get(name) or '')} |"
            for name in commands]
    out += ["", "Examples, as `linkage-fmu --help` prints them:", "", "```sh"]
    out += [line.strip() if not line.startswith("      ") else "    " + line.strip()
            for line in (parser.epilog or "").splitlines()[1:]]
    out += ["```", ""]
    for name, command in commands.items():
        out += [f"## `linkage-fmu {name}`", "", f"{_cell(helps.get(name) or '')}.", "",
                "```text", _usage(command), "```", ""]
        out += _arguments(command) + [""]
    return "\n".join(out).rstrip("\n") + "\n"


if __name__ == "__main__":
    sys.stdout.write(markdown())
