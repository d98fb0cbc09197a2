"""The README shows what the project ships (its examples run as doctests)."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).parents[1]


def test_the_readme_shows_the_example_file_as_it_is():
    """The description file in "Your own linkage" is examples/coupler_four_bar.toml, byte
    for byte (the README's doctest loads that file)."""
    readme = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", readme, flags=re.S)
    assert blocks == [(ROOT / "examples" / "coupler_four_bar.toml").read_text()]
