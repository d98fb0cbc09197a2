"""docs/cli.md is what the code writes, and what it writes holds every command and every
option that ``linkage-fmu --help`` and each command's ``--help`` print."""

from __future__ import annotations

import difflib
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from linkage_fmu.manual import cli_reference

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "cli.md"
REGENERATE = "regenerate it: python -m linkage_fmu.manual.cli_reference > docs/cli.md"


def run(*args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT / "src")] + [p for p in [os.environ.get("PYTHONPATH")] if p])}
    return subprocess.run([sys.executable, *args], env=env, capture_output=True, text=True,
                          encoding="utf-8", cwd=ROOT)


@pytest.fixture(scope="module")
def text() -> str:
    return cli_reference.markdown()


def test_the_committed_reference_is_what_the_code_writes(text):
    written = DOC.read_text(encoding="utf-8")
    if written != text:
        diff = difflib.unified_diff(written.splitlines(), text.splitlines(), "docs/cli.md",
                                    "cli_reference.markdown()", n=1, lineterm="")
        pytest.fail(f"docs/cli.md is not what the code writes; {REGENERATE}\n"
                    + "\n".join(list(diff)[:40]))


def test_the_script_prints_the_reference(text):
    done = run("-m", "linkage_fmu.manual.cli_reference")
    assert done.returncode == 0, done.stderr
    assert done.stdout == text


def section(text: str, command: str) -> str:
    start = text.index(f"## `linkage-fmu {command}`\n")
    end = text.find("\n## ", start + 1)
    return text[start:end if end > 0 else len(text)]


def test_every_command_and_option_of_the_help_is_in_it(text):
    """The commands, from the usage line ``linkage-fmu --help`` prints; each command's
    options, from the lines of its ``--help`` that start with a dash: each is a row of
    the command's table, and its help's first words are in that row."""
    top = run("-m", "linkage_fmu", "--help")
    assert top.returncode == 0, top.stderr
    commands = re.search(r"\{([a-z,]+)\}", top.stdout).group(1).split(",")
    assert len(commands) >= 10 and "table" in commands and "reference" in commands
    assert re.findall(r"^## `linkage-fmu (\w+)`$", text, flags=re.M) == commands
    for command in commands:
        done = run("-m", "linkage_fmu", command, "--help")
        assert done.returncode == 0, done.stderr
        own = section(text, command)
        options = re.findall(r"^  (-[-\w]+(?:, --[-\w]+)?)(?: ([A-Z_]+[^ ]*))?(?:  +(.*))?$",
                             done.stdout, flags=re.M)
        assert options, command
        for option, _metavar, help_start in options:
            if option in ("-h, --help",):
                continue
            row = next((r for r in own.splitlines()
                        if r.startswith(f"| `{option}")), None)
            assert row is not None, (command, option)
            if help_start:
                assert " ".join(help_start.split()[:3]) in row, (command, option)


def example_commands(text: str) -> list[str]:
    """The commands of the examples in ``text`` (a ``--help``'s, from its line
    ``examples:``, or a page's ``sh`` block): a line that starts with ``linkage-fmu``
    opens one, the lines after a line ending in a backslash continue it."""
    commands, going_on = [], False
    for line in text.splitlines():
        if going_on:
            commands[-1] += "\n" + line
        elif line.strip().startswith("linkage-fmu"):
            commands.append(line)
        going_on = line.endswith("\\")
    return commands


def refused_by_the_parser(command: str) -> str | None:
    """What the command line's own parser says of ``command`` (split as bash splits it,
    the comment aside), with the loads of the linkage it names added as main() adds
    them; None if it parses. The linkage must be a preset or a file of the project."""
    import contextlib
    import io
    import shlex

    from linkage_fmu import cli

    argv = shlex.split(command.replace("\\\n", " "), comments=True)  # as bash joins lines
    assert argv[0] == "linkage-fmu", command
    argv = argv[1:]
    parser = cli.build_parser()
    name, named = cli._named_linkage(argv)
    if name in cli.LOAD_COMMANDS:
        if named is None:
            return "names no preset and no description file of the project"
        cli._load_options(cli.subcommands(parser)[name], named)
    said = io.StringIO()
    with contextlib.redirect_stderr(said):
        try:
            args = parser.parse_args(argv)
        except SystemExit:
            return said.getvalue().strip() or "refused"
    if name not in cli.LOAD_COMMANDS and getattr(args, "linkage", None) is not None:
        try:
            cli.description(args.linkage)
        except Exception as err:  # noqa: BLE001 -- the reason is the answer
            return f"{args.linkage}: {err}"
    return None


def bash_syntax_error(command: str) -> str | None:
    """bash's complaint at ``command`` read as a script (``bash -n``: nothing runs),
    or None."""
    done = subprocess.run(["bash", "-n"], input=command + "\n", capture_output=True,
                          text=True)
    return done.stderr.strip() if done.returncode else None


def test_the_parts_of_the_checks_of_the_examples_refuse_what_they_should(monkeypatch):
    """The exact case of a pasted example that failed: its result written after it in
    parentheses is a syntax error of bash; an option of no command, a load of another
    linkage and a file that is not there are refused; the same as a comment passes."""
    monkeypatch.chdir(ROOT)
    bad = "linkage-fmu build --native --drive four_bar        (dist/native/FourBarDrive.fmu)"
    assert "syntax error" in bash_syntax_error(bad)
    good = "linkage-fmu build --native --drive four_bar  # dist/native/FourBarDrive.fmu"
    assert bash_syntax_error(good) is None and refused_by_the_parser(good) is None
    assert "--drve" in refused_by_the_parser("linkage-fmu build --native --drve four_bar")
    assert "--F_P" in refused_by_the_parser("linkage-fmu table four_bar --F_P 80")
    assert refused_by_the_parser("linkage-fmu table my_linkage.toml").startswith("names no")
    assert refused_by_the_parser("linkage-fmu info my_linkage.toml").startswith(
        "my_linkage.toml: ")
    assert refused_by_the_parser("linkage-fmu table examples/coupler_four_bar.toml "
                                 "--F_P 80 --T4 120") is None
    assert example_commands("examples:\n  linkage-fmu a \\\n      b\n  linkage-fmu c\n") == [
        "  linkage-fmu a \\\n      b", "  linkage-fmu c"]


def test_every_example_is_a_command_that_works_when_pasted(text, monkeypatch):
    """Each example of ``linkage-fmu --help`` and of each command's ``--help`` (the
    same, printed by every command that shows examples), and of the page's examples
    block: bash reads it without a syntax error (its result is a comment), it names a
    preset or a file of the project (from the project's folder), and the command line's
    parser takes each of its options (the linkage's loads included)."""
    monkeypatch.chdir(ROOT)
    from linkage_fmu import cli

    parser = cli.build_parser()
    helps = {"linkage-fmu": parser.format_help()}
    helps |= {f"linkage-fmu {name}": command.format_help()
              for name, command in cli.subcommands(parser).items()}
    shown = {where: example_commands(help_text.partition("\nexamples:\n")[2])
             for where, help_text in helps.items()}
    assert len(shown["linkage-fmu"]) >= 25
    assert shown["linkage-fmu table"] == shown["linkage-fmu"]
    (page,) = re.findall(r"Examples, as `linkage-fmu --help` prints them:\n\n```sh\n(.*?)```",
                         text, flags=re.S)
    shown["docs/cli.md"] = example_commands(page)
    assert [c.strip() for c in shown["docs/cli.md"]] == [
        "\n".join(line.strip() if k == 0 else "    " + line.strip()
                  for k, line in enumerate(c.strip().splitlines()))
        for c in shown["linkage-fmu"]]
    # every command that shows examples shows the main help's: each is checked once
    assert all(commands in ([], shown["linkage-fmu"]) for commands in shown.values()
               if commands is not shown["docs/cli.md"])
    problems = {}
    for where in ("linkage-fmu", "docs/cli.md"):
        for command in shown[where]:
            said = bash_syntax_error(command) or refused_by_the_parser(command)
            if said:
                problems.setdefault(where, []).append((command, said))
    assert problems == {}
    assert "linkage-fmu build --native --drive four_bar   # dist/native/FourBarDrive.fmu" \
        in shown["linkage-fmu"][-2]
