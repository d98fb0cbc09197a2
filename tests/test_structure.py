"""The package's structure, read from its source: no module uses another module's private
names, the imports (function-level ones included) form no cycle, the kernels import
nothing of the package above them, and the descriptions nothing above the mechanism."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "linkage_fmu"
#: names with a leading underscore that are public by convention (namedtuple's API)
CONVENTIONAL = {"_replace", "_asdict", "_fields", "_make"}


def modules() -> dict[str, Path]:
    """Dotted module name -> file, for every module of the package."""
    out = {}
    for path in sorted((SRC / PACKAGE).rglob("*.py")):
        parts = path.relative_to(SRC).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


def imports(name: str, path: Path, known: dict) -> set[str]:
    """The package's modules that module ``name`` imports, at any level of its code."""
    tree = ast.parse(path.read_text())
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parts = parts[:len(parts) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            # a submodule, or a name the module ``base`` defines
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base
                       for a in node.names]
        elif isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        else:
            continue
        found.update(t for t in targets if t in known and t != name)
    return found


def graph() -> dict[str, set[str]]:
    known = modules()
    return {name: imports(name, path, known) for name, path in known.items()}


def test_the_imports_have_no_cycle():
    g = graph()
    state: dict[str, int] = {}

    def visit(node, path):
        if state.get(node) == 1:
            cycle = path[path.index(node):] + [node]
            pytest.fail("import cycle: " + " -> ".join(cycle))
        if state.get(node) == 2:
            return
        state[node] = 1
        for nxt in sorted(g[node]):
            visit(nxt, path + [node])
        state[node] = 2

    for node in sorted(g):
        visit(node, [])


def test_the_kernels_import_nothing_above_them():
    """linkage_fmu.kernels and its modules import only themselves and the compiler
    finder (a leaf that imports nothing of the package)."""
    g = graph()
    assert g[f"{PACKAGE}.ccompiler"] == set()
    for name, targets in g.items():
        if name.startswith(f"{PACKAGE}.kernels"):
            outside = {t for t in targets if not t.startswith(f"{PACKAGE}.kernels")}
            assert outside <= {f"{PACKAGE}.ccompiler"}, (name, outside)


def stands_on(g: dict[str, set[str]], roots: set[str]) -> set[str]:
    """The modules ``roots`` and every module they import, directly or not."""
    found, todo = set(), list(roots)
    while todo:
        name = todo.pop()
        if name not in found:
            found.add(name)
            todo.extend(g[name])
    return found


def test_descriptions_import_nothing_above_the_mechanism():
    """linkage_fmu.descriptions and its modules import only themselves, the mechanism,
    the parameters (the kinds and rules of the values a description builds it with) and
    what these stand on: not the presets, the FMUs, the command line, the plots, sweeps
    or the manual, which stand on the descriptions."""
    g = graph()
    below = stands_on(g, {f"{PACKAGE}.mechanism", f"{PACKAGE}.parameters"})
    assert f"{PACKAGE}.groups" in below and f"{PACKAGE}.presets" not in below
    descriptions = {n for n in g if n == f"{PACKAGE}.descriptions"
                    or n.startswith(f"{PACKAGE}.descriptions.")}
    for name in descriptions:
        above = g[name] - below - descriptions
        assert not above, (name, above)


def own_names(tree: ast.Module) -> set[str]:
    """The private names a module defines: functions, classes, their methods and
    attributes, and module-level assignments."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            names.add(node.attr)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, (ast.AnnAssign,)) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    slots = [n for n in ast.walk(tree) if isinstance(n, ast.Assign) and
             any(isinstance(t, ast.Name) and t.id == "__slots__" for t in n.targets)]
    for node in slots:
        for elt in getattr(node.value, "elts", []):
            if isinstance(elt, ast.Constant):
                names.add(elt.value)
    return names


def test_no_module_uses_another_modules_private_names():
    for name, path in modules().items():
        tree = ast.parse(path.read_text())
        own = own_names(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                private = [a.name for a in node.names if a.name.startswith("_")
                           and not a.name.startswith("__")]
                assert not private, (name, node.lineno, private)
            elif isinstance(node, ast.Attribute):
                attr = node.attr
                if attr.startswith("_") and not attr.startswith("__") and \
                        attr not in CONVENTIONAL:
                    assert attr in own, (name, node.lineno, attr)


def module_names(name: str, path: Path, tree: ast.Module, known: dict) -> dict[str, str]:
    """Local name -> the package module it is bound to by an import of module ``name``
    (``from . import friction``, ``from .. import newton as n``, ``import linkage_fmu.x``),
    at any level of its code."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    bound = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parts = parts[:len(parts) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            for a in node.names:
                if f"{base}.{a.name}" in known:
                    bound[a.asname or a.name] = f"{base}.{a.name}"
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name in known:
                    bound[a.asname or a.name.partition(".")[0]] = \
                        a.name if a.asname else a.name.partition(".")[0]
    return bound


def module_of(node: ast.expr, bound: dict, known: dict) -> str | None:
    """The package module the expression ``node`` names (a name bound to one, or a
    submodule of one: ``friction.kinetostatics``), else None."""
    if isinstance(node, ast.Name):
        return bound.get(node.id)
    if isinstance(node, ast.Attribute):
        outer = module_of(node.value, bound, known)
        if outer is not None and f"{outer}.{node.attr}" in known:
            return f"{outer}.{node.attr}"
    return None


def test_no_module_uses_a_private_name_of_a_module_it_imports():
    """``kinetostatics._solve`` from friction: a private name read through an imported
    module, which the test above passes where the reading module defines a name of the
    same spelling."""
    known = modules()
    found = []
    for name, path in known.items():
        tree = ast.parse(path.read_text())
        bound = module_names(name, path, tree, known)
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and node.attr.startswith("_") and \
                    not node.attr.startswith("__") and node.attr not in CONVENTIONAL:
                target = module_of(node.value, bound, known)
                if target is not None and target != name:
                    found.append((name, node.lineno, f"{target}.{node.attr}"))
    assert not found


def test_the_linear_algebra_is_a_leaf():
    """linkage_fmu.linalg imports nothing of the package, and at its import only numpy:
    mpmath is imported by the solve that uses it (the package imports without it)."""
    assert graph()[f"{PACKAGE}.linalg"] == set()
    tree = ast.parse((SRC / PACKAGE / "linalg.py").read_text())
    top = {a.name for node in tree.body if isinstance(node, ast.Import) for a in node.names}
    top |= {node.module for node in tree.body if isinstance(node, ast.ImportFrom)}
    assert top == {"__future__", "numpy"}
