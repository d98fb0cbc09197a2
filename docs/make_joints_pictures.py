"""Make the pictures of docs/joints-and-links.md and paste into it what ``linkage-fmu info``
prints for its examples, from the example files as they are.

    python docs/make_joints_pictures.py            (from the project root)

Each picture is the project's own plot, ``linkage-fmu plot FILE --what KIND ...`` (the
command is :data:`PICTURES`, and the page shows it under the picture). Each block of
the page between ``<!-- linkage-fmu info FILE [groups] -->`` and ``<!-- end -->`` is
replaced by the output of ``linkage-fmu info FILE`` (with ``groups``, its lines up to
the groups' list's end). Run it again after an example file changes: the test of the
page (tests/test_readme.py) fails while a pasted output is not what ``info`` prints.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "joints-and-links.md"
#: the arguments of ``linkage-fmu plot`` of each picture, from the project root
PICTURES = [
    ["examples/triad_six_bar.toml", "--what", "linkage", "--theta-deg", "30",
     "-o", "docs/triad_six_bar_forces.png"],
    ["examples/triad_six_bar.toml", "--what", "torque",
     "-o", "docs/triad_six_bar_torque.png"],
    ["examples/jansen.toml", "--what", "linkage", "--theta-deg", "90",
     "-o", "docs/jansen_forces.png"],
    ["examples/klann.toml", "--what", "linkage", "--theta-deg", "0",
     "-o", "docs/klann_forces.png"],
]
#: a pasted output: its opening marker (the file, and ``groups`` for only its groups)
#: and the fenced block up to the closing marker
BLOCK = re.compile(r"(<!-- linkage-fmu info (\S+)( groups)? -->\n)(.*?)(<!-- end -->)",
                   flags=re.S)


def info(path: str, groups_only: bool) -> str:
    """What ``linkage-fmu info path`` prints (run from the project root); with
    ``groups_only``, its lines before ``parameters:``."""
    from linkage_fmu.cli import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        status = main(["info", str(ROOT / path)])
    if status != 0:
        raise SystemExit(f"make_joints_pictures.py: linkage-fmu info {path} failed "
                         f"(exit {status})")
    text = out.getvalue()
    if groups_only:
        text = text[:text.index("\nparameters:") + 1]
    return text


def pasted(page: str) -> str:
    """``page`` with each info block replaced by what ``info`` prints now."""
    def replace(m: re.Match) -> str:
        return f"{m.group(1)}```text\n{info(m.group(2), bool(m.group(3)))}```\n{m.group(5)}"

    return BLOCK.sub(replace, page)


def main() -> int:
    import matplotlib

    matplotlib.use("Agg")
    from linkage_fmu.cli import main as cli

    os.chdir(ROOT)  # the commands are the page's, from the project root
    for arguments in PICTURES:
        if cli(["plot", *arguments]) != 0:
            print(f"make_joints_pictures.py: linkage-fmu plot {' '.join(arguments)} failed",
                  file=sys.stderr)
            return 1
    PAGE.write_text(pasted(PAGE.read_text()))
    print(f"pasted the output of linkage-fmu info into {PAGE.relative_to(ROOT)}",
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
