"""mkdocs hooks.

- The committed benchmark results (benchmarks/results/, outside docs/) are part of the
  site, so that the performance page shows their figures and links to their tables and
  CSV files rather than copies of them.
- The pages link to them (and the changelog to the pages) by their paths in the
  repository, relative to the page, as GitHub resolves them; the site's paths differ
  (docs/ is its root, the results are under benchmarks/results/ in it), so links are
  mapped from the one to the other here.
- The pages that only mkdocs can build (the changelog, the API reference) say so to a
  reader of the sources on GitHub, in a line the site leaves out.
- The docstrings' Sphinx roles (``:func:`~linkage_fmu.Mechanism.solve```), which
  mkdocstrings leaves as text, become cross-references to the API reference.
"""

from __future__ import annotations

import functools
import html as htmllib
import posixpath
import re
from pathlib import Path

import griffe
from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
RESULTS = ROOT / "benchmarks" / "results"
PACKAGE = "linkage_fmu"

#: the line of a page that tells a reader on GitHub the page is built by mkdocs
SOURCE_NOTE = re.compile(r"^> This page is built by mkdocs\b.*\n+", flags=re.M)
#: an inline link or image: ``](target)``, its target without a title
LINK = re.compile(r"(\]\()([^)\s]+)(\))")
#: a Sphinx role before inline code in a docstring (``:func:`simulate```) as the API
#: pages render it, ``:func:<code>simulate</code>``; or the heading of a documented
#: object (the docstrings that follow are its own)
ROLE_OR_HEADING = re.compile(
    r":(?:func|meth|class|mod|data|attr|exc|obj):\s*<code>(?P<text>[^<]*)</code>"
    rf'|<h\d id="(?P<object>{PACKAGE}(?:\.\w+)*)"')
#: a role's text with a title of its own: ``title <target>`` (HTML-escaped)
TITLED = re.compile(r"^(?P<title>.*?)\s*&lt;(?P<target>[\w.~]+)&gt;$")


def on_files(files, config):
    for path in sorted(RESULTS.iterdir()):
        if path.suffix in (".md", ".png", ".csv"):
            files.append(File.generated(config, f"benchmarks/results/{path.name}",
                                        abs_src_path=str(path)))
    return files


def site_path(path: Path) -> str | None:
    """The site's path (from docs/) of the repository's file ``path``, or None for a
    file outside the site."""
    for folder, prefix in ((DOCS, ""), (RESULTS, "benchmarks/results/")):
        if path.is_relative_to(folder):
            return prefix + path.relative_to(folder).as_posix()
    return None


def map_links(markdown: str, source: Path, page_uri: str) -> str:
    """The relative links of ``markdown`` (the text of the repository's file ``source``)
    written from the site's page ``page_uri`` rather than from ``source``."""
    def target(match: re.Match) -> str:
        link = match.group(2)
        if re.match(r"^[a-z][a-z0-9+.-]*:|^[#/]", link, flags=re.I):
            return match.group(0)
        path, anchor, rest = link.partition("#")
        site = site_path(Path(posixpath.normpath((source.parent / path).as_posix())))
        if not path or site is None:
            return match.group(0)
        mapped = posixpath.relpath(site, posixpath.dirname(page_uri) or ".")
        return match.group(1) + mapped + anchor + rest + match.group(3)
    return LINK.sub(target, markdown)


def on_page_markdown(markdown, page, config, files):
    """The page without its note for GitHub, its links the site's; the changelog page
    is CHANGELOG.md whole (its snippet line, expanded here)."""
    markdown = SOURCE_NOTE.sub("", markdown)
    if page.file.src_uri == "changelog.md":
        changelog = ROOT / "CHANGELOG.md"
        text = map_links(changelog.read_text(encoding="utf-8"), changelog, page.file.src_uri)
        return markdown.replace('--8<-- "CHANGELOG.md"', text)
    return map_links(markdown, Path(page.file.abs_src_path), page.file.src_uri)


@functools.cache
def package() -> griffe.Module:
    return griffe.load(PACKAGE, search_paths=[str(ROOT / "src")])


def lookup(path: str) -> griffe.Object | None:
    """The package's object at ``path`` (through its imports), or None."""
    head, _, rest = path.partition(".")
    if head != PACKAGE:
        return None
    try:
        found = package()[rest] if rest else package()
        return found.final_target if isinstance(found, griffe.Alias) else found
    except (KeyError, ValueError, griffe.AliasResolutionError, griffe.CyclicAliasError):
        return None


@functools.cache
def paths() -> tuple[str, ...]:
    """The path of each object the package defines (its imports aside)."""
    found, todo = [], [package()]
    while todo:
        obj = todo.pop()
        found.append(obj.path)
        todo.extend(member for member in obj.members.values()
                    if not member.is_alias and not member.name.startswith("__"))
    return tuple(sorted(found))


def resolve(name: str, context: str | None) -> str | None:
    """The full path of the object ``name`` in a role of the docstring of ``context``
    (a documented object's path), as Sphinx finds it: a full name as written, else in
    the object, its class, its module and the packages above that; a leading dot also
    matches the one object whose path ends with the name."""
    relative = name.startswith(".")
    name = name.lstrip(".")
    if name.split(".")[0] == PACKAGE:
        return name if lookup(name) else None
    scopes = []
    obj = lookup(context) if context else None
    if obj is not None:
        if obj.is_class or obj.is_module:
            scopes.append(obj.path)
        if obj.parent is not None and obj.parent.is_class:
            scopes.append(obj.parent.path)
        module = obj.module.path.split(".")
        scopes += [".".join(module[:n]) for n in range(len(module), 0, -1)]
    else:
        scopes.append(PACKAGE)
    for scope in scopes:
        if (found := lookup(f"{scope}.{name}")) is not None:
            return found.path
    if relative:
        ends = [path for path in paths() if path.endswith("." + name)]
        if len(ends) == 1:
            return ends[0]
    return None


def cross_references(html: str) -> str:
    """``html`` (an API page) with each role's code a cross-reference to its object,
    shown as Sphinx shows it (``~`` leaves the last name); an object the site does not
    document, or that is not found, stays code (an optional reference)."""
    context = None

    def replace(match: re.Match) -> str:
        nonlocal context
        if match.group("object"):
            context = match.group("object")
            return match.group(0)
        text = match.group("text")
        titled = TITLED.match(text)
        target = titled.group("target") if titled else text
        target = target.strip().rstrip("()")
        if titled:
            title = titled.group("title")
        elif target.startswith("~"):
            title = target.split(".")[-1] + ("()" if text.endswith("()") else "")
        else:
            title = text.lstrip(".")
        identifier = resolve(target.lstrip("~"), context) or target.lstrip("~.")
        return (f'<autoref identifier="{htmllib.escape(identifier)}" optional>'
                f"<code>{title}</code></autoref>")

    return ROLE_OR_HEADING.sub(replace, html)


def on_page_content(html, page, config, files):
    return cross_references(html)
