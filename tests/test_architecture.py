"""The package's structure: layers with one-way imports, no import circle, the 5-bar used through
its package (the mechanisms' parts: tests/mechanisms/test_parts.py)."""

import ast
from pathlib import Path

import fivebar_drake

PACKAGE = Path(fivebar_drake.__file__).parent
# a module may import from its own layer and the layers before it; analysis, simulation and
# optimal are side by side and do not import each other; the studies wrap the pipeline (the 5-bar's study)
LAYERS = {"core": 0, "actuators": 0.2, "verdicts": 0.3, "gaits": 0.5, "mechanisms": 1, "robots": 2, "analysis": 3, "optimal": 3, "simulation": 4,
          "pipeline": 5, "studies": 6, "catalog": 7, "sweep": 7, "envelope": 8, "codesign": 9,
          "entry": 9.5, "cli": 10, "__main__": 11}


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports() -> dict[str, set[str]]:
    """Each module of the package -> the package modules it imports (a name imported from a
    package that is one of its modules counts as that module)."""
    graph = {}
    for path in PACKAGE.rglob("*.py"):
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("fivebar_drake"):
                subs = {f"{node.module}.{a.name}" for a in node.names}
                found |= {m for m in subs if (PACKAGE.parent / (m.replace(".", "/") + ".py"))
                          .exists()} or {node.module}
            elif isinstance(node, ast.Import):
                found |= {a.name for a in node.names if a.name.startswith("fivebar_drake")}
        graph[module_name(path)] = found
    return graph


def layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def test_imports_run_one_way_between_layers():
    wrong = [f"{m} -> {d}" for m, deps in imports().items() for d in deps
             if layer(m) in LAYERS and layer(d) in LAYERS and layer(m) != layer(d)
             and LAYERS[layer(d)] >= LAYERS[layer(m)]]
    assert not wrong, wrong


def test_no_import_circle():
    graph, state, circles = imports(), {}, []

    def visit(m, stack):
        state[m] = "open"
        for d in graph.get(m, ()):
            if state.get(d) == "open":
                circles.append(stack[stack.index(d):] + [d])
            elif d in graph and d not in state:
                visit(d, stack + [d])
        state[m] = "done"

    for m in graph:
        if m not in state:
            visit(m, [m])
    assert not circles, circles


def test_the_five_bar_is_used_through_its_package():
    inside = "fivebar_drake.mechanisms.fivebar"
    wrong = [f"{m} -> {d}" for m, deps in imports().items() if not m.startswith(inside)
             for d in deps if d.startswith(inside + ".")]
    assert not wrong, wrong



def test_no_isinstance_on_a_maneuver_outside_its_module():
    """A maneuver owns its contract (its needs by kind: optimal/needs.py; its phases:
    FootPath.lands, pushes; its events and achievement: its methods): no module but the paths'
    own asks isinstance or issubclass of a path class, under any name it imports it by."""
    import ast
    import inspect

    from fivebar_drake import gaits

    paths = {name for name, obj in vars(gaits).items()
             if inspect.isclass(obj) and issubclass(obj, gaits.FootPath)}
    package = Path(gaits.__file__).resolve().parent.parent
    offenders = []
    for file in package.rglob("*.py"):
        if file.parent.name == "gaits":           # the paths' own modules
            continue
        tree = ast.parse(file.read_text())
        alias = {}
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(
                    "fivebar_drake.gaits"):
                alias.update({a.asname or a.name: a.name for a in node.names})
        for node in ast.walk(tree):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                    and node.func.id in ("isinstance", "issubclass") and len(node.args) == 2):
                kinds = node.args[1].elts if isinstance(node.args[1], ast.Tuple) else [node.args[1]]
                for kind in kinds:
                    name = kind.id if isinstance(kind, ast.Name) else getattr(kind, "attr", "")
                    if alias.get(name, name if name in alias.values() else None) in paths:
                        offenders.append(f"{file.relative_to(package)}:{node.lineno}")
    assert offenders == []
