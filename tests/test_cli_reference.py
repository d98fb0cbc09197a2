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

from linkage_fmu import cli_reference

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "cli.md"
REGENERATE = "regenerate it: python -m linkage_fmu.cli_reference > docs/cli.md"


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
    done = run("-m", "linkage_fmu.cli_reference")
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
