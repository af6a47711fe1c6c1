"""The layers of docs/design.md §8, held by reading every module's imports (including the ones
inside functions): physics/ knows nothing above it; figures draw from arrays; nothing imports
the workflow's entry points."""
import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "tensegrity"
LAYERS = ("physics", "workspace", "locomotion", "validation", "io", "render", "stages", "figure_stages",
          "cli")
# what each layer must never import (besides itself)
FORBIDDEN = {
    "physics": {"workspace", "locomotion", "validation", "io", "render", "stages", "figure_stages", "cli"},
    "render": {"io", "locomotion", "validation", "stages", "figure_stages", "cli"},
    "workspace": {"locomotion", "validation", "render", "stages", "figure_stages", "cli"},
    "locomotion": {"validation", "render", "stages", "figure_stages", "cli"},
    "validation": {"render", "stages", "figure_stages", "cli"},
    "io": {"render", "stages", "cli", "validation"},
}
# Design studies (issue 12): studies/ builds on physics, workspace, locomotion and io; only the
# entry points (study_stages, cli) import it.
LAYERS += ("studies", "study_stages")
FORBIDDEN["studies"] = {"validation", "render", "stages", "figure_stages", "cli", "study_stages"}
for _layer in ("physics", "render", "workspace", "locomotion", "validation", "io"):
    FORBIDDEN[_layer] = FORBIDDEN[_layer] | {"studies", "study_stages"}


def _layer_imports(path: Path, pkg: Path = PKG) -> set[str]:
    """The tensegrity layers a module of package directory `pkg` imports, resolving relative
    imports."""
    rel = path.relative_to(pkg.parent).with_suffix("").parts  # ('tensegrity', 'physics', 'x')
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = list(rel[:len(rel) - node.level])
                target = base + (node.module.split(".") if node.module else [])
            else:
                target = (node.module or "").split(".")
            if target[:1] != ["tensegrity"]:
                continue
            if len(target) > 1:
                out.add(target[1])
            else:  # from tensegrity import x
                out.update(a.name for a in node.names)
        elif isinstance(node, ast.Import):
            for a in node.names:
                parts = a.name.split(".")
                if parts[0] == "tensegrity" and len(parts) > 1:
                    out.add(parts[1])
    return out & set(LAYERS)


MODULES = sorted(p for p in PKG.rglob("*.py") if p.parent != PKG)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PKG)))
def test_module_imports_no_higher_layer(path):
    layer = path.relative_to(PKG).parts[0]
    bad = _layer_imports(path) & FORBIDDEN.get(layer, set())
    assert not bad, f"{path.relative_to(PKG)} ({layer}/) imports {sorted(bad)}"


def test_the_check_sees_relative_and_lazy_imports(tmp_path):
    """The test itself can fail: a lazy relative import of io from physics is caught."""
    mod = tmp_path / "tensegrity" / "physics" / "probe.py"
    mod.parent.mkdir(parents=True)
    mod.write_text("def f():\n    from ..io import datasets\n    return datasets\n")
    assert _layer_imports(mod, tmp_path / "tensegrity") == {"io"}


def test_modules_are_of_a_size_a_reader_holds_in_mind():
    sizes = {str(p.relative_to(PKG)): len(p.read_text().splitlines()) for p in PKG.rglob("*.py")}
    big = {k: v for k, v in sizes.items() if v > 400}
    assert not big, f"modules over 400 lines: {big}"


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
    for path in PKG.rglob("*.py"):
        if path.parent == PKG / "physics" / "kernel":  # numba: typed by the compiled signatures
            continue
        for name, fn in _public_functions(path):
            args = [a for a in fn.args.args + fn.args.kwonlyargs if a.arg not in ("self", "cls")]
            args += [a for a in (fn.args.vararg, fn.args.kwarg) if a is not None]
            if fn.returns is None or any(a.annotation is None for a in args):
                missing.append(f"{path.relative_to(PKG)}:{fn.lineno} {name}")
    assert not missing, "public functions without type hints:\n" + "\n".join(missing)
