"""The layers of docs/design.md §8, held by reading every module's imports (including the ones
inside functions and under TYPE_CHECKING): every module of the package belongs to a layer, a
layer imports only the layers below it, and no modules import each other in a circle."""

import ast
import functools
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "tensegrity"
_DOMAIN = ("physics", "paper", "workspace", "locomotion", "validation", "studies", "calibration")
_LEAVES = ("atomic", "version")  # standard library only: anyone may import them
# what each layer may import besides itself: the layers below it (docs/design.md §8)
ALLOWED = {
    "physics": set(),
    "paper": set(),
    "workspace": {"physics", "paper"},
    "locomotion": {"physics", "paper", "workspace"},
    "validation": {"physics", "paper", "workspace", "locomotion"},
    "studies": {"physics", "paper", "workspace", "locomotion", "validation"},
    "calibration": {"physics", "paper"},
    "render": {"physics", "paper", *_LEAVES},
    "bridges": {"physics", "paper", *_LEAVES},  # issue 33: models for other simulators (MJCF)
    "envs": {"physics", "paper", *_LEAVES},  # issue 33: Gymnasium environments over the kernel
    "atomic": set(),
    "version": set(),
    "io": {*_DOMAIN, *_LEAVES},
    "stages": {*_DOMAIN, *_LEAVES, "render", "io"},
    "cli": {*_DOMAIN, *_LEAVES, "render", "io", "stages", "bridges", "envs"},
    "__init__": {*_DOMAIN, *_LEAVES, "io"},
}


def _module_name(path: Path, pkg: Path = PKG) -> str:
    """'tensegrity.physics.frames' of .../tensegrity/physics/frames.py (a package: its __init__)."""
    parts = path.relative_to(pkg.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, pkg: Path = PKG) -> set[str]:
    """The tensegrity modules (dotted names) a module imports, relative imports resolved."""
    rel = path.relative_to(pkg.parent).with_suffix("").parts  # ('tensegrity', 'physics', 'x')
    here = list(rel[:-1]) if rel[-1] == "__init__" else list(rel[:-1])
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = here[: len(here) - (node.level - 1)] if node.level else []
            target = base + (node.module.split(".") if node.module else [])
            if target[:1] != ["tensegrity"]:
                continue
            out.add(".".join(target))
            out.update(".".join(target + [a.name]) for a in node.names)  # `from . import x`: maybe a module
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.split(".")[0] == "tensegrity")
    return out


MODULES = sorted(PKG.rglob("*.py"))
NAMES = {_module_name(p): p for p in MODULES}


def _layer(name: str) -> str:
    parts = name.split(".")
    return "__init__" if len(parts) == 1 else parts[1]


@functools.cache  # parsed once for the ~140 parametrised cases (read-only)
def _edges() -> dict[str, set[str]]:
    """module -> the modules of the package it imports: names that are not modules dropped, and
    a package whose module is imported by name (`from .. import paper`: tensegrity.paper, not
    tensegrity)."""
    out = {}
    for name, p in NAMES.items():
        mods = {m for m in _imports(p) if m in NAMES and m != name}
        out[name] = {m for m in mods if not any(o.startswith(m + ".") for o in mods)}
    return out


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PKG)))
def test_module_imports_no_higher_layer(path):
    name = _module_name(path)
    layer = _layer(name)
    assert layer in ALLOWED, f"{name}: a module of no layer ({layer}); give it one in docs/design.md §8"
    bad = {_layer(m) for m in _edges()[name]} - ALLOWED[layer] - {layer}
    assert not bad, f"{path.relative_to(PKG)} ({layer}) imports {sorted(bad)}"


def test_no_import_circle():
    """Tarjan's strongly connected components of the module graph: every one a single module."""
    edges, index, low, stack, on, circles = _edges(), {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                circles.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    assert not circles, f"modules that import each other: {circles}"


def test_the_checks_see_relative_lazy_imports_and_circles(tmp_path):
    """The tests themselves can fail: a lazy relative import of io from physics is seen."""
    mod = tmp_path / "tensegrity" / "physics" / "probe.py"
    mod.parent.mkdir(parents=True)
    mod.write_text("def f():\n    from ..io import datasets\n    return datasets\n")
    assert "tensegrity.io.datasets" in _imports(mod, tmp_path / "tensegrity")
    init = tmp_path / "tensegrity" / "physics" / "__init__.py"
    init.write_text("from . import probe\n")
    assert "tensegrity.physics.probe" in _imports(init, tmp_path / "tensegrity")


def test_modules_are_of_a_size_a_reader_holds_in_mind():
    sizes = {str(p.relative_to(PKG)): len(p.read_text().splitlines()) for p in MODULES}
    big = {k: v for k, v in sizes.items() if v > 300}
    assert not big, f"modules over 300 lines: {big}"


def _public_functions(path: Path):
    """(name, node) of the module- and class-level public functions of a module."""

    def visit(body):
        for node in body:
            if isinstance(node, ast.ClassDef):
                yield from visit(node.body)
            elif isinstance(node, ast.FunctionDef) and not node.name.startswith("_"):
                yield node.name, node

    yield from visit(ast.parse(path.read_text()).body)


def test_public_functions_have_type_hints():
    missing = []
    for path in MODULES:
        if path.parent == PKG / "physics" / "kernel":  # numba: typed by the compiled signatures
            continue
        for name, fn in _public_functions(path):
            args = [a for a in fn.args.args + fn.args.kwonlyargs if a.arg not in ("self", "cls")]
            args += [a for a in (fn.args.vararg, fn.args.kwarg) if a is not None]
            if fn.returns is None or any(a.annotation is None for a in args):
                missing.append(f"{path.relative_to(PKG)}:{fn.lineno} {name}")
    assert not missing, "public functions without type hints:\n" + "\n".join(missing)
