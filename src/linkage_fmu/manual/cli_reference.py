"""The command-line reference (Markdown), written from the parser of :mod:`linkage_fmu.cli`,
so that it lists every command and option the command line has, with its help.

``python -m linkage_fmu.manual.cli_reference > docs/cli.md`` writes the documentation's
page (a test keeps it current).

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

from ..cli import LOAD_COMMANDS, Parser, build_parser, subcommands

INTRO = """\
<!-- written by python -m linkage_fmu.manual.cli_reference > docs/cli.md; do not edit -->

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


#: the longest line of a code block the site shows whole (tests/test_docs.py)
WIDTH = 80


def _usage(parser: Parser, width: int = WIDTH) -> str:
    """``parser``'s usage as ``--help`` prints it, its commands' choices ``COMMAND`` (the
    table of commands follows it), in lines of at most ``width`` characters, each after
    the first under the first argument.

    Examples
    --------
    >>> print(_usage(build_parser().commands["simulate"], 60))
    linkage-fmu simulate [-h] [--set NAME=VALUE] --tau VALUE
                         --t-end VALUE [--n N] [--theta0 VALUE]
                         [--omega0 VALUE] [--flywheel VALUE]
                         [--outputs OUTPUTS [OUTPUTS ...]] [--csv]
                         [-o OUTPUT] linkage
    >>> _usage(build_parser())
    'linkage-fmu [-h] [--version] COMMAND ...'
    """
    text = " ".join(parser.format_usage().removeprefix("usage: ").split())
    if parser.commands:
        text = text.replace("{" + ",".join(parser.commands) + "}", "COMMAND")
    words, depth = [""], 0  # split at the spaces outside brackets
    for char in text:
        if char == " " and depth == 0:
            words.append("")
            continue
        depth += (char in "[({") - (char in "])}")
        words[-1] += char
    for k in range(len(words) - 1, 0, -1):  # a required option with its value
        if words[k - 1].startswith("-") and not words[k].startswith(("-", "[")):
            words[k - 1:k + 1] = [words[k - 1] + " " + words[k]]
    prog = len(parser.prog.split())
    lines = [" ".join(words[:prog])]
    indent = " " * (len(lines[0]) + 1)
    for word in words[prog:]:
        if len(lines[-1]) + 1 + len(word) > width and lines[-1].strip():
            lines.append(indent + word)
        else:
            lines[-1] += " " + word
    return "\n".join(lines)


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
