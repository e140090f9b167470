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


def modules(package, root=REPO):
    d = os.path.join(root, package)
    return sorted(f[:-3] for f in os.listdir(d) if f.endswith(".py"))


def imports(package, module, root=REPO):
    """(package or external name, module in the package or None) of every import in a
    module, at any depth (functions included)."""
    path = os.path.join(root, package, f"{module}.py")
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


def layer_violations(package, root=REPO):
    ours = set(PURE + BLENDER)
    out = []
    for module in modules(package, root):
        for top, _ in imports(package, module, root):
            if package in PURE and top in BLENDER_MODULES:
                out.append(f"{package}/{module}.py imports {top}: pure code must not")
            if top in ours and top not in ALLOWED[package]:
                out.append(f"{package}/{module}.py imports {top}/ against the data flow")
    return out


def cycles(package, root=REPO):
    mods = modules(package, root)
    graph = {m: {sub for top, sub in imports(package, m, root) if top == package and sub in mods} for m in mods}
    state, out = {}, []

    def visit(m, path):
        state[m] = "open"
        for n in sorted(graph[m]):
            if state.get(n) == "open":
                out.append(" -> ".join(path + [m, n]))
            elif n not in state:
                visit(n, path + [m])
        state[m] = "done"
    for m in mods:
        if m not in state:
            visit(m, [])
    return out


@pytest.mark.parametrize("package", PURE + BLENDER)
def test_imports_follow_the_layers(package):
    assert layer_violations(package) == []


@pytest.mark.parametrize("package", PURE + BLENDER)
def test_no_import_cycles_inside_a_package(package):
    assert cycles(package) == []


def test_no_module_past_400_lines():
    long = []
    for package in PURE + BLENDER:
        for module in modules(package):
            n = sum(1 for _ in open(os.path.join(REPO, package, f"{module}.py")))
            if n > 400:
                long.append(f"{package}/{module}.py ({n} lines)")
    assert long == []


def test_the_checks_see_wrong_imports_and_cycles(tmp_path):
    """On a made-up tree: bpy in a pure package, an import against the data flow inside
    a function, and a cycle through a function-level import are all found."""
    (tmp_path / "model").mkdir()
    (tmp_path / "agents").mkdir()
    (tmp_path / "model" / "a.py").write_text("from . import b\n")
    (tmp_path / "model" / "b.py").write_text("def f():\n    from .a import x\n")
    (tmp_path / "agents" / "c.py").write_text("import bpy\n\ndef g():\n    from ..strokes import layers\n")
    assert cycles("model", tmp_path) == ["a -> b -> a"]
    found = layer_violations("agents", tmp_path)
    assert "agents/c.py imports bpy: pure code must not" in found
    assert "agents/c.py imports strokes/ against the data flow" in found
    assert layer_violations("model", tmp_path) == []
