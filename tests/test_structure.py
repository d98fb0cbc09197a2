"""The package's structure, read from its source: no module uses another module's private
names, the imports (function-level ones included) form no cycle, the kernels import
nothing of the package above them but the errors, the descriptions nothing above the
mechanism, and every error the package raises is a LinkageFmuError."""

from __future__ import annotations

import ast
import builtins
import importlib
import inspect
from pathlib import Path

import pytest

from linkage_fmu.errors import LinkageFmuError

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


def imported_from(name: str, path: Path, node: ast.ImportFrom) -> str:
    """The absolute name of the module a ``from ... import`` of module ``name`` reads."""
    base = node.module or ""
    if node.level:
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        parts = package.split(".")
        parts = parts[:len(parts) - node.level + 1]
        base = ".".join(parts + ([base] if base else []))
    return base


def imports(name: str, path: Path, known: dict) -> set[str]:
    """The package's modules that module ``name`` imports, at any level of its code."""
    tree = ast.parse(path.read_text())
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = imported_from(name, path, node)
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
    """linkage_fmu.kernels and its modules import only themselves, the errors (a leaf
    that imports nothing of the package) and the compiler finder (which imports only the
    errors)."""
    g = graph()
    assert g[f"{PACKAGE}.errors"] == set()
    assert g[f"{PACKAGE}.ccompiler"] <= {f"{PACKAGE}.errors"}
    for name, targets in g.items():
        if name.startswith(f"{PACKAGE}.kernels"):
            outside = {t for t in targets if not t.startswith(f"{PACKAGE}.kernels")}
            assert outside <= {f"{PACKAGE}.ccompiler", f"{PACKAGE}.errors"}, (name, outside)


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
    bound = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = imported_from(name, path, node)
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


#: the package's layers, bottom first: a module imports its own layer's and those below.
#: A package (``groups``, ``kernels``) stands for its modules; the package root and the
#: applications come last.
LAYERS = (
    ("numbers and kernels", {"units", "errors", "numerics", "linalg", "newton", "printing",
                             "ccompiler", "kernels", "expressions", "interpolation",
                             "tables"}),
    ("the parts of a linkage", {"pairs", "drivers", "groups", "parameters", "bodies",
                                "loads", "outputs", "inertia"}),
    ("the physics", {"kinetostatics", "friction", "diagnostics", "ranges", "motion",
                     "driven_motion", "flywheel", "free_body"}),
    ("the formula sequence", {"inputs", "evaluation"}),
    ("solving", {"solver", "precise", "equations", "equation_files", "effort_places"}),
    ("the mechanism", {"mechanism"}),
    ("descriptions", {"descriptions"}),
    ("applications", {"presets", "fmi", "sweep", "optimize", "plot", "manual", "cli",
                      "report", "__main__", ""}),
)


def layer_of(name: str) -> int:
    short = name[len(PACKAGE) + 1:] if name != PACKAGE else ""
    top = short.partition(".")[0]
    for k, (_, members) in enumerate(LAYERS):
        if short in members or top in members:
            return k
    raise AssertionError(f"{name} is in no layer of LAYERS: add it where it belongs")


def test_no_import_arrow_runs_upwards():
    """Each module imports only modules of its own layer or of the layers below
    (:data:`LAYERS`): the data flows from the numbers up to the applications, and a
    module placed in no layer fails the test."""
    g = graph()
    upward = [(name, LAYERS[layer_of(name)][0], target, LAYERS[layer_of(target)][0])
              for name, targets in sorted(g.items()) for target in sorted(targets)
              if layer_of(target) > layer_of(name)]
    assert not upward


def test_class_mechanism_is_a_facade_under_350_lines():
    """The mechanism holds what a linkage is and hands its work to the modules below
    (the formula sequence, the inputs, the solver): its class stays under 350 lines."""
    tree = ast.parse((SRC / PACKAGE / "mechanism.py").read_text())
    (cls,) = [n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Mechanism"]
    assert cls.end_lineno - cls.lineno + 1 < 350


def mechanism_methods() -> set[str]:
    """The methods of class Mechanism (not its properties)."""
    tree = ast.parse((SRC / PACKAGE / "mechanism.py").read_text())
    (cls,) = [n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Mechanism"]
    return {f.name for f in cls.body if isinstance(f, ast.FunctionDef)
            and not any(isinstance(d, ast.Name) and d.id == "property"
                        for d in f.decorator_list)}


def test_the_solver_calls_no_method_of_the_mechanism():
    """The solver reads the mechanism's data and evaluates it through
    :mod:`linkage_fmu.evaluation` and its input table; it calls none of the mechanism's
    methods (a call of a name the mechanism's methods have, on anything but the solver
    itself, fails). ``rebuild`` is data: the linkage's own way to be built again."""
    methods = {m for m in mechanism_methods() if not m.startswith("__")}
    assert {"solve", "kinematics", "inputs"} <= methods
    known = modules()
    path = SRC / PACKAGE / "solver.py"
    tree = ast.parse(path.read_text())
    bound = module_names(f"{PACKAGE}.solver", path, tree, known)

    def own(value: ast.expr) -> bool:  # the solver itself, or a module it imports
        return (isinstance(value, ast.Name) and value.id == "self") or \
            module_of(value, bound, known) is not None

    calls = [(n.lineno, ast.unparse(n.func)) for n in ast.walk(tree)
             if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)
             and n.func.attr in methods and not own(n.func.value)]
    assert not calls


#: the modules that hold the pair kinds, and the description layer, whose drawings name
#: a pair by the letter of an Assur group's formula (R or P) before any pair class exists
#: (a group type's ``recognise``, which reads such a drawing ``drawn``, is skipped too)
KIND_HOMES = ("pairs.py", "descriptions")


def test_no_code_outside_the_pair_classes_asks_a_pairs_kind():
    """No module but :mod:`linkage_fmu.pairs` tests which kind a pair is: no
    ``isinstance``/``type(...) is`` of a pair class, and no reading of what only one kind
    has (a normal, a ``revolute`` flag); each kind answers through its methods."""
    from linkage_fmu import pairs

    kinds = {name for name, value in vars(pairs).items()
             if isinstance(value, type) and issubclass(value, pairs.Pair)}
    assert {"Pair", "Revolute", "Prismatic"} <= kinds
    found = []
    for name, path in modules().items():
        rel = path.relative_to(SRC / PACKAGE).as_posix()
        if any(rel == home or rel.startswith(home + "/") for home in KIND_HOMES):
            continue
        tree = ast.parse(path.read_text())
        # a group type's recognise (and what it calls with the drawing, ``drawn``) reads
        # a drawing, whose joints are R or P by letter
        drawing = {id(n) for f in ast.walk(tree) if isinstance(f, ast.FunctionDef)
                   and "drawn" in [a.arg for a in f.args.args] for n in ast.walk(f)}
        for node in ast.walk(tree):
            if id(node) in drawing:
                continue
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
                    node.func.id in ("isinstance", "issubclass") and len(node.args) == 2:
                named = {n.id for n in ast.walk(node.args[1]) if isinstance(n, ast.Name)}
                named |= {n.attr for n in ast.walk(node.args[1]) if isinstance(n, ast.Attribute)}
                if named & kinds:
                    found.append((name, node.lineno, "isinstance"))
            elif isinstance(node, ast.Compare) and any(
                    isinstance(op, (ast.Is, ast.IsNot, ast.Eq, ast.NotEq)) for op in node.ops):
                named = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}
                if named & (kinds - {"Pair"}):
                    found.append((name, node.lineno, "type comparison"))
            elif isinstance(node, ast.Attribute) and node.attr in ("normal", "revolute",
                                                                   "prismatic"):
                found.append((name, node.lineno, node.attr))
    assert not found


#: the exceptions the package may raise that are not its own errors, each for a reason:
#: argparse's protocol for an option's type (argparse catches it and prints the usage),
#: an abstract method's, and an iterator's end
NOT_OURS = {"argparse.ArgumentTypeError", "NotImplementedError", "StopIteration"}
#: ``raise`` of an error made before, where the source does not say its class: the
#: error a failed trace was kept with, and the method that makes a state's error (both
#: make library errors, which the construction check below covers)
MADE_BEFORE = {(f"{PACKAGE}.solver", "k.error"), (f"{PACKAGE}.solver", "self._unbounded")}


def local_imports(module, tree: ast.Module) -> dict:
    """Name -> object for the names a function of ``module`` imports (``from .errors
    import SelfLockingError`` inside a function)."""
    bound = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            source = importlib.import_module("." * node.level + (node.module or ""),
                                             module.__package__)
            for a in node.names:
                if hasattr(source, a.name):
                    bound[a.asname or a.name] = getattr(source, a.name)
    return bound


def resolve(module, node: ast.expr, local: dict):
    """The object the name or attribute chain ``node`` is in ``module`` (its globals, the
    names its functions import, the builtins), or None where it is not such a name (a
    local variable, ``self``)."""
    if isinstance(node, ast.Attribute):
        outer = resolve(module, node.value, local)
        return None if outer is None else getattr(outer, node.attr, None)
    if isinstance(node, ast.Name):
        for names in (vars(module), local, vars(builtins)):
            if node.id in names:
                return names[node.id]
    return None


def is_error(obj) -> bool:
    return isinstance(obj, type) and issubclass(obj, BaseException) and \
        not issubclass(obj, Warning)


def raised() -> list[tuple[str, int, str, object]]:
    """``(module, line, expression, object)`` for every ``raise X(...)``, ``raise X`` and
    every call of an exception class (an error made to be raised elsewhere) of the
    package, X a name or an attribute chain."""
    found = []
    for name, path in modules().items():
        if name.endswith(".__main__"):
            continue  # it runs the command line; its code raises nothing
        module = importlib.import_module(name)
        tree = ast.parse(path.read_text())
        local = local_imports(module, tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Raise) and node.exc is not None:
                target = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
                if isinstance(target, (ast.Name, ast.Attribute)):
                    found.append((name, node.lineno, ast.unparse(target),
                                  resolve(module, target, local)))
            elif isinstance(node, ast.Call) and isinstance(node.func, (ast.Name, ast.Attribute)):
                obj = resolve(module, node.func, local)
                if is_error(obj):
                    found.append((name, node.lineno, ast.unparse(node.func), obj))
    return list(dict.fromkeys(found))  # a raise's call is seen as a call too


def test_every_error_the_package_raises_is_a_linkage_fmu_error():
    """Read from the source: each error raised or made is a LinkageFmuError (and, by the
    test below, the builtin error it names), but for NOT_OURS and MADE_BEFORE; a
    ``raise ValueError(...)`` fails it."""
    wrong = []
    for name, line, expr, obj in raised():
        if expr in NOT_OURS:
            continue
        if obj is None:
            if (name, expr) not in MADE_BEFORE:
                wrong.append((name, line, expr, "not resolved"))
        elif is_error(obj) and not issubclass(obj, LinkageFmuError):
            wrong.append((name, line, expr, obj.__name__))
    assert not wrong


def test_the_check_sees_a_builtin_error():
    tree = ast.parse("def f(x):\n    raise ValueError(f'x = {x}')\n")
    raise_ = next(n for n in ast.walk(tree) if isinstance(n, ast.Raise))
    obj = resolve(importlib.import_module(f"{PACKAGE}.errors"), raise_.exc.func, {})
    assert obj is ValueError and not issubclass(obj, LinkageFmuError)


#: the builtin error each of the package's errors has always been
BUILTIN = {"AssemblyError": ValueError, "SingularPositionError": ValueError,
           "SelfLockingError": ValueError, "OverflowInputError": ValueError,
           "LinkageError": ValueError, "OutputError": ValueError, "LoadError": ValueError,
           "ParameterError": ValueError, "InputError": ValueError,
           "InputTypeError": TypeError, "ComputationError": RuntimeError,
           "DependencyError": ImportError, "UsageError": Exception,
           "CompilerError": RuntimeError, "NoFeasibleDesignError": ValueError,
           "TracingError": RuntimeError, "FMURunError": RuntimeError,
           "BinaryError": ValueError, "DescriptionError": ValueError,
           "DecompositionError": ValueError, "CycleError": ValueError,
           "MissingFFmpegError": RuntimeError}


def test_each_error_class_is_a_linkage_fmu_error_and_its_builtin():
    classes = {}
    for name in modules():
        if name.endswith(".__main__"):
            continue
        module = importlib.import_module(name)
        for _, cls in inspect.getmembers(module, is_error):
            if cls.__module__ == name and cls is not LinkageFmuError:
                classes[cls.__name__] = cls
    assert set(classes) == set(BUILTIN)
    for cls_name, cls in classes.items():
        assert issubclass(cls, LinkageFmuError), cls_name
        assert issubclass(cls, BUILTIN[cls_name]), cls_name
