"""The package's floors, checked from its import graph (the installed package's source).

Each layer may import only the layers listed for it in :data:`MAY_IMPORT`
(and itself).  Besides:

- the float64 reference imports no ``vtkRendering*`` module and no mapper (the
  mappers may use its float64 kernels, for the few rays bricks compute on the
  CPU; it never uses theirs);
- the core (everything but the pyvista front ends ``mipcast.filters`` and
  ``mipcast.app``) imports pyvista only inside functions;
- the ParaView plugin imports no pyvista at all;
- module-level imports have no cycles;
- no module imports a private (``_name``) from another layer.
"""
import ast
from pathlib import Path

import mipcast

PACKAGE = Path(mipcast.__file__).resolve().parent

#: Layer -> the layers it may import ("mipcast" is the package's __init__).
MAY_IMPORT = {
    "core": set(),
    "shaders": set(),
    "reference": {"core"},
    "io": {"core"},
    "data_fixtures": {"core"},
    # the mappers compute a few rays on the CPU (bricks' outline and face rays) with the float64 kernels
    "mappers": {"core", "shaders", "reference"},
    "methods": {"core", "reference", "mappers"},
    "offscreen": {"core", "mappers", "methods"},
    "distributed": {"core", "mappers", "methods", "offscreen"},
    "mipcast": {"core", "mappers", "methods"},
    "bench": {"core", "reference", "mappers", "methods", "offscreen", "distributed", "io", "data_fixtures",
              "mipcast"},
    "filters": {"core", "mappers", "methods", "offscreen", "io", "data_fixtures", "mipcast"},
    "app": {"core", "reference", "mappers", "methods", "offscreen", "io", "data_fixtures", "bench",
            "filters", "mipcast"},
    "plugin": {"core", "reference", "mappers", "methods", "offscreen", "distributed", "io", "data_fixtures",
               "mipcast"},
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "mipcast"


def imports(tree: ast.Module):
    """(imported module, names, at module level) for every import statement."""
    top = set(id(node) for node in ast.iter_child_nodes(tree))
    for node in ast.walk(tree):
        module_level = id(node) in top or _in_top_level_block(tree, node)
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, (), module_level
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            yield node.module, tuple(a.name for a in node.names), module_level


def _in_top_level_block(tree, node) -> bool:
    for statement in tree.body:
        if isinstance(statement, (ast.If, ast.Try)) and any(n is node for n in ast.walk(statement)):
            return not any(isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef))
                           and any(m is node for m in ast.walk(n)) for n in ast.walk(statement))
    return False


def graph():
    modules = {}
    for path in PACKAGE.rglob("*.py"):
        if "macros" in path.parts:
            continue
        modules[module_name(path)] = list(imports(ast.parse(path.read_text(encoding="utf-8"))))
    return modules


MODULES = graph()


def test_the_graph_is_the_installed_package():
    assert "mipcast.methods" in MODULES and "mipcast.core.parameters" in MODULES
    assert len(MODULES) > 40


def targets(target: str, names: tuple) -> list:
    """``from mipcast import methods`` imports the module ``mipcast.methods``."""
    submodules = [f"{target}.{n}" for n in names if f"{target}.{n}" in MODULES]
    return submodules if submodules and len(submodules) == len(names) else [target]


def test_each_layer_imports_only_the_layers_below_it():
    wrong = []
    for module, found in MODULES.items():
        allowed = MAY_IMPORT[layer(module)] | {layer(module)}
        for target, names, _ in found:
            for name in targets(target, names):
                if (name == "mipcast" or name.startswith("mipcast.")) and layer(name) not in allowed:
                    wrong.append(f"{module} imports {name}")
    assert not wrong, "\n".join(wrong)


def test_the_reference_imports_no_vtk_rendering_and_no_mapper():
    for module, found in MODULES.items():
        if layer(module) == "reference":
            for target, _, _ in found:
                assert not target.startswith("vtkmodules.vtkRendering"), (module, target)
                assert not target.startswith("mipcast.mappers"), (module, target)


def test_pyvista_is_imported_lazily_outside_the_pyvista_front_ends_and_never_by_the_plugin():
    for module, found in MODULES.items():
        for target, _, module_level in found:
            if target.split(".")[0] != "pyvista":
                continue
            assert layer(module) != "plugin", f"{module} imports pyvista"
            if module_level:
                assert layer(module) in ("filters", "app"), f"{module} imports pyvista at import time"


def test_module_level_imports_have_no_cycles():
    edges = {m: {t for t, _, top in found if top and t in MODULES} for m, found in MODULES.items()}
    # "from mipcast.core import shading" names a submodule: an edge to it too
    for module, found in MODULES.items():
        for target, names, top in found:
            if top:
                edges[module] |= {f"{target}.{n}" for n in names if f"{target}.{n}" in MODULES}
    state = {}

    def visit(node, path):
        state[node] = "open"
        for nxt in sorted(edges[node]):
            if nxt == node or nxt == node.rsplit(".", 1)[0]:
                continue  # a package importing its own submodule, or a module its package
            if state.get(nxt) == "open":
                raise AssertionError("import cycle: " + " -> ".join(path + [nxt]))
            if nxt not in state:
                visit(nxt, path + [nxt])
        state[node] = "done"

    for module in sorted(edges):
        if module not in state:
            visit(module, [module])


def test_no_module_imports_another_layers_private_names():
    wrong = [f"{module}: from {target} import {name}"
             for module, found in MODULES.items() for target, names, _ in found
             if target.startswith("mipcast") and layer(target) != layer(module)
             for name in names if name.startswith("_") and name != "__version__"]
    assert not wrong, "\n".join(wrong)
