"""The package's shape: imports flow one way down the wings (no cycle and no climb, at module and
at package level, also through imports inside functions), every module stays small enough to
hold one concept, and a module's header says what it depends on."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "cloth"
#: Most lines a module of cloth/ may have (docs/architecture.md).
MAX_LINES = 600
#: The wings, top to bottom: a module may import its own wing and the wings below it, never one
#: above (docs/architecture.md). "" is the ground floor: cloth itself, errors, io, progress.
ORDER = (
    "api",
    "cli",
    "stages",
    "pipeline",
    "files",
    "figures",
    "results",
    "solvers",
    "contact",
    "garment",
    "case",
    "bodies",
    "materials",
    "",
)
#: Modules outside the order: ``python -m cloth`` is the command line itself.
TOP = {"cloth.__main__": "cli"}


def _modules() -> dict[str, Path]:
    found = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


def import_graph() -> dict[str, set[str]]:
    """Module -> the cloth modules it imports anywhere in its text (module level or inside
    functions), as ``import a.b`` or ``from a.b import c`` (c a module or a name in a.b)."""
    modules = _modules()
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        deps: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parents = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join([*parents, base] if base else parents)
                for alias in node.names:
                    full = f"{base}.{alias.name}"
                    deps.add(full if full in modules else base)
            elif isinstance(node, ast.Import):
                deps.update(alias.name for alias in node.names)
        graph[name] = {d for d in deps if d in modules and d != name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def wing(module: str) -> str:
    """The wing of a cloth module: its sub-package, or "" for the ground floor."""
    if module in TOP:
        return TOP[module]
    parts = module.split(".")
    return parts[1] if len(parts) > 2 or (len(parts) == 2 and parts[1] in ORDER) else ""


def climbs(graph: dict[str, set[str]]) -> list[str]:
    """Every import that climbs the wings' order, as 'importer -> imported'."""
    rank = {name: i for i, name in enumerate(ORDER)}
    return [
        f"{module} -> {dep}"
        for module, deps in sorted(graph.items())
        for dep in sorted(deps)
        if rank[wing(dep)] < rank[wing(module)]
    ]


def package_graph(graph: dict[str, set[str]]) -> dict[str, set[str]]:
    """The wings' graph: wing -> the other wings its modules import (anywhere in their text)."""
    wings: dict[str, set[str]] = {name: set() for name in ORDER}
    for module, deps in graph.items():
        wings[wing(module)].update(wing(dep) for dep in deps if wing(dep) != wing(module))
    return wings


#: Modules whose functions import cloth late by design, and why (their docstring says so too).
LATE = {
    "cloth.cli.handlers": "a verb imports its stage when it runs: `cloth --version` imports none"
}


def hidden_imports() -> list[str]:
    """Imports of cloth inside a function without a comment on their line saying why (outside
    the modules of `LATE`)."""
    found = []
    for name, path in _modules().items():
        if name in LATE:
            continue
        lines = path.read_text().splitlines()
        for node in ast.walk(ast.parse("\n".join(lines))):
            if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            for sub in ast.walk(node):
                names = (
                    [sub.module or ""]
                    if isinstance(sub, ast.ImportFrom)
                    else [a.name for a in sub.names]
                    if isinstance(sub, ast.Import)
                    else []
                )
                if any(n.split(".")[0] == "cloth" for n in names) and "#" not in "".join(
                    lines[sub.lineno - 1 : sub.end_lineno]
                ):
                    found.append(f"{name}:{sub.lineno}")
    return found


def test_the_order_checks_find_a_climb_and_a_package_loop():
    graph = {"cloth.garment.grid": {"cloth.files.state"}, "cloth.files.state": {"cloth.io"}}
    assert climbs(graph) == ["cloth.garment.grid -> cloth.files.state"]
    assert climbs({"cloth.files.state": {"cloth.garment.grid", "cloth.errors"}}) == []
    # modules without a cycle between them, wings with one: bodies.a -> figures.b -> bodies.c
    loop = {
        "cloth.bodies.a": {"cloth.figures.b"},
        "cloth.figures.b": {"cloth.bodies.c"},
        "cloth.bodies.c": set(),
    }
    assert cycles(loop) == [] and cycles(package_graph(loop)) == [["bodies", "figures"]]
    assert wing("cloth.errors") == "" and wing("cloth") == "" and wing("cloth.solvers") == "solvers"


def test_no_import_climbs_the_wings():
    graph = import_graph()
    assert set(map(wing, graph)) <= set(ORDER), "a module outside the wings: add it to ORDER"
    assert climbs(graph) == []
    assert cycles(package_graph(graph)) == []


def test_imports_of_cloth_are_at_module_level():
    assert hidden_imports() == []


def test_the_cycle_finder_finds_a_cycle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert cycles(graph) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_the_imports_of_cloth_have_no_cycle():
    graph = import_graph()
    assert graph["cloth.cli"] >= {"cloth.cli.parser"}  # the walk sees imports
    assert "cloth.stages.results" in graph["cloth.cli.handlers"] or (
        "cloth.stages" in graph["cloth.cli.handlers"]
    )
    assert cycles(graph) == []


def test_no_module_is_over_max_lines():
    sizes = {name: len(path.read_text().splitlines()) for name, path in _modules().items()}
    assert {name: n for name, n in sizes.items() if n > MAX_LINES} == {}


def private_imports() -> list[str]:
    """``from cloth.x import _name`` in a cloth module other than cloth.x: a private name used
    across modules (the linear factor and the grid's operators have public faces for that)."""
    found = []
    modules = _modules()
    for name, path in modules.items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("cloth"):
                found += [
                    f"{name}:{node.lineno} {alias.name}"
                    for alias in node.names
                    if alias.name.startswith("_")
                    and not alias.name.startswith("__")
                    and node.module != name
                ]
    return found


def test_no_module_imports_another_modules_private_name():
    assert private_imports() == []


def case_readers(packages: tuple[str, ...] = ("solvers", "contact")) -> list[str]:
    """Modules of ``packages`` that read a case: ``<x>.case`` or import the `Case` type. The
    solvers and the skin models take `Settings` and `Skin`, never the case
    (docs/architecture.md)."""
    found = []
    for name, path in _modules().items():
        if name.split(".")[1:2] and name.split(".")[1] in packages:
            for node in ast.walk(ast.parse(path.read_text())):
                reads = isinstance(node, ast.Attribute) and node.attr == "case"
                imports = isinstance(node, ast.ImportFrom) and any(
                    alias.name == "Case" for alias in node.names
                )
                if reads or imports:
                    found.append(f"{name}:{node.lineno}")
    return found


def test_solvers_and_skin_models_never_read_the_case():
    assert case_readers() == []
    assert case_readers(("stages",))  # the walk sees reads: the stages hand the case on


def test_every_module_of_the_package_is_linted():
    """ruff's file selection holds every module of the package: an exclude meant for the
    results folder ("results") once matched cloth/results/ too, whose 11 modules then went
    unlinted with 5 findings."""
    import subprocess
    import sys

    ruff = Path(sys.executable).parent / "ruff"
    if not ruff.exists():
        pytest.skip("ruff is not installed (the dev extra)")
    shown = subprocess.run(
        [str(ruff), "check", "--show-files", "."],
        cwd=PACKAGE.parent,
        capture_output=True,
        text=True,
    ).stdout
    linted = {Path(line.strip()).resolve() for line in shown.splitlines() if line.strip()}
    modules = {path.resolve() for path in PACKAGE.rglob("*.py")}
    assert sorted(map(str, modules - linted)) == []


#: Methods that write a file (their first argument, or the object they are called on, is
#: where): each must run inside ``with atomic_output(...)``.
WRITE_CALLS = {
    "write_text",
    "write_bytes",
    "to_netcdf",
    "savefig",
    "export",
    "saveas",
    "save",
    "savez",
    "savetxt",
    "tofile",
    "to_csv",
    "write_html",
    "write_image",
}
#: Files opened for writing that are not outputs, by module, with the reason.
NOT_OUTPUTS = {
    "cloth.solvers.relax": "/proc/self/clear_refs: a kernel control file, reset for a benchmark",
    "cloth.solvers.cholesky": "os.devnull: CHOLMOD's C-level warnings silenced",
}


def _writes(node: ast.Call) -> bool:
    """Whether ``node`` writes a file: a `WRITE_CALLS` call, or ``open`` with a mode that
    writes."""
    func = node.func
    name = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
    if name in WRITE_CALLS and isinstance(func, ast.Attribute):  # a method: mesh.export(p)
        return True
    if name == "open":
        modes = [a.value for a in node.args[1:2] if isinstance(a, ast.Constant)]
        modes += [k.value.value for k in node.keywords if k.arg == "mode"]
        return any(isinstance(m, str) and set(m) & set("wax+") for m in modes)
    return False


def _atomic(item: ast.withitem) -> bool:
    call = item.context_expr
    if not isinstance(call, ast.Call):
        return False
    func = call.func
    return (func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")) == (
        "atomic_output"
    )


def unguarded_writes(source: str) -> list[int]:
    """Lines of ``source`` that write a file outside a ``with atomic_output(...)`` block (the
    block's own ``with`` line counts as inside: ``with atomic_output(p) as t, t.open("w")``)."""
    tree = ast.parse(source)
    guarded: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.With) and any(_atomic(item) for item in node.items):
            for sub in ast.walk(node):
                if isinstance(sub, ast.Call):
                    guarded.add(id(sub))
    return sorted(
        node.lineno
        for node in ast.walk(tree)
        if isinstance(node, ast.Call) and _writes(node) and id(node) not in guarded
    )


def test_the_writer_check_finds_a_file_written_in_place():
    assert unguarded_writes("def f(p):\n    p.write_text('x')\n") == [2]
    assert unguarded_writes("def f(p):\n    with open(p, 'w') as h:\n        h.write('x')\n") == [2]
    assert unguarded_writes("def f(ds, p):\n    ds.to_netcdf(p)\n") == [2]
    inside = "def f(p):\n    with atomic_output(p) as t, t.open('w') as h:\n        h.write('x')\n"
    assert unguarded_writes(inside) == []
    assert unguarded_writes("def f(p):\n    with open(p) as h:\n        h.read()\n") == []


def test_every_file_the_package_writes_goes_through_the_atomic_writer():
    """A file the tool writes is whole or absent, never half-written (`cloth.io.atomic_output`):
    no module opens one for writing outside it."""
    found = []
    for name, path in _modules().items():
        if name in NOT_OUTPUTS:
            continue
        found += [f"{name}:{line}" for line in unguarded_writes(path.read_text())]
    assert found == []


def test_every_subpackage_is_in_the_wheel_s_package_list():
    """pyproject.toml lists the wheel's packages by hand (the data/ folder is mapped in as
    cloth.data, which rules out setuptools' discovery): a new subpackage must be listed too."""
    import tomllib

    listed = set(
        tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text())["tool"]["setuptools"][
            "packages"
        ]
    )
    found = {
        ".".join(path.parent.relative_to(PACKAGE.parent).parts)
        for path in PACKAGE.rglob("__init__.py")
    }
    mapped = {"cloth.data", "cloth.workflow", "cloth.config", "cloth.schemas"}  # no __init__
    assert found <= listed and listed - found == mapped
