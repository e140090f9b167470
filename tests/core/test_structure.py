"""The code's shape: data flows one way (model -> blackboard -> agents -> strokes ->
pipeline -> cli; the Blender layer on top), the pure packages never import Blender,
no import cycles inside a package, no module past 400 lines."""
import ast
import os

import pytest
from conftest import REPO

PURE = ("model", "blackboard", "agents", "strokes", "pipeline", "cli")
BLENDER = ("blobtree_nodes", "operators", "grease_pencil")
BLENDER_MODULES = {"bpy", "mathutils", "bpy_extras", "addon_utils", "bmesh", "gpu"}
# what each package may import from the extension (itself included)
ALLOWED = {
    "model": {"model"},
    "blackboard": {"model", "blackboard"},
    "agents": {"model", "blackboard", "agents"},
    "strokes": {"model", "blackboard", "agents", "strokes"},
    "pipeline": {"model", "blackboard", "agents", "strokes", "pipeline"},
    "cli": {"model", "blackboard", "agents", "strokes", "pipeline", "cli"},
    "grease_pencil": set(PURE) | {"grease_pencil"},
    "blobtree_nodes": set(PURE) | {"blobtree_nodes", "grease_pencil"},
    "operators": set(PURE) | set(BLENDER),
}


def modules(package):
    d = os.path.join(REPO, package)
    return sorted(f[:-3] for f in os.listdir(d) if f.endswith(".py"))


def imports(package, module):
    """(package or external name, module in the package or None) of every import in a
    module, at any depth (functions included)."""
    path = os.path.join(REPO, package, f"{module}.py")
    tree = ast.parse(open(path).read(), path)
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(a.name.split(".")[0], None) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                out.append((node.module.split(".")[0], None))
            elif node.level == 1:
                if node.module:
                    out.append((package, node.module.split(".")[0]))
                else:
                    out += [(package, a.name) for a in node.names]
            else:           # from ..pkg[.mod] import x
                parts = (node.module or "").split(".")
                if parts[0]:
                    out.append((parts[0], parts[1] if len(parts) > 1 else None))
                else:
                    out += [(a.name, None) for a in node.names]
    return out


@pytest.mark.parametrize("package", PURE + BLENDER)
def test_imports_follow_the_layers(package):
    ours = set(PURE + BLENDER)
    for module in modules(package):
        for top, _ in imports(package, module):
            if package in PURE:
                assert top not in BLENDER_MODULES, f"{package}/{module}.py imports {top}: pure code must not"
            if top in ours:
                assert top in ALLOWED[package], f"{package}/{module}.py imports {top}/ against the data flow"


@pytest.mark.parametrize("package", PURE + BLENDER)
def test_no_import_cycles_inside_a_package(package):
    graph = {m: {sub for top, sub in imports(package, m) if top == package and sub in modules(package)}
             for m in modules(package)}
    state = {}

    def visit(m, path):
        state[m] = "open"
        for n in sorted(graph[m]):
            assert state.get(n) != "open", f"import cycle in {package}/: {' -> '.join(path + [m, n])}"
            if n not in state:
                visit(n, path + [m])
        state[m] = "done"
    for m in graph:
        if m not in state:
            visit(m, [])


def test_no_module_past_400_lines():
    long = []
    for package in PURE + BLENDER:
        for module in modules(package):
            n = sum(1 for _ in open(os.path.join(REPO, package, f"{module}.py")))
            if n > 400:
                long.append(f"{package}/{module}.py ({n} lines)")
    assert long == []


def test_the_checks_see_a_wrong_import(tmp_path, monkeypatch):
    """The import walk finds imports in functions and relative imports two levels up."""
    found = imports("model", "format")
    assert ("json", None) in found and ("os", None) in found         # os is imported inside save()
    assert ("agents", "surface") in imports("agents", "tracer")
    assert ("model", "tolerances") in imports("agents", "tracer")
