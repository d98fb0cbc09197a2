"""mkdocs hooks: the committed benchmark results (benchmarks/results/, outside docs/)
are part of the site, so that the performance page shows their figures and links to
their tables and CSV files rather than copies of them."""

from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File

RESULTS = Path(__file__).resolve().parents[1] / "benchmarks" / "results"


def on_files(files, config):
    for path in sorted(RESULTS.iterdir()):
        if path.suffix in (".md", ".png", ".csv"):
            files.append(File.generated(config, f"benchmarks/results/{path.name}",
                                        abs_src_path=str(path)))
    return files


def on_page_markdown(markdown, page, config, files):
    """The changelog page is CHANGELOG.md whole (its snippet line, expanded here), with
    its links to the documentation, written from the project's root (docs/X.md), made
    the site's (X.md)."""
    if page.file.src_uri == "changelog.md":
        text = (RESULTS.parents[1] / "CHANGELOG.md").read_text(encoding="utf-8")
        return markdown.replace('--8<-- "CHANGELOG.md"', text.replace("](docs/", "]("))
    return markdown


#: a Sphinx role before inline code in a docstring (``:func:`simulate```), as the API
#: pages render it: ":func: <code>simulate</code>"
ROLE = re.compile(r":(?:func|meth|class|mod|data|attr|exc|obj):\s*(?=<code>)")


def on_page_content(html, page, config, files):
    """The docstrings' Sphinx roles, which mkdocstrings leaves as text, dropped before
    their code."""
    return ROLE.sub("", html)
