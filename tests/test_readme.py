"""The README shows what the project ships (its examples run as doctests)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).parents[1]


def test_the_readme_shows_the_example_files_as_they_are():
    """The description file in "Your own linkage" is examples/coupler_four_bar.toml, byte
    for byte, and every line of the engine's excerpt (its comments after ``#`` aside, and
    the ``# ...`` line) is a line of examples/engine.toml (the README's doctests load
    those files)."""
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", readme, flags=re.S)
    coupler = (ROOT / "examples" / "coupler_four_bar.toml").read_text()
    assert len(blocks) == 2 and coupler in blocks
    excerpt = next(b for b in blocks if b != coupler)
    engine = [line.strip() for line in
              (ROOT / "examples" / "engine.toml").read_text().splitlines()]
    for line in excerpt.splitlines():
        code = line.split(" #")[0].strip()
        if code and code != "# ...":
            assert code in engine, line
