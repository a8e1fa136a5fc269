"""The shape of the package: imports go down the layers, never in a circle; modules stay short.

The imports of every module of ``cosmos`` are read from its source (``ast``,
nothing is imported), including imports inside functions and under
``TYPE_CHECKING``: a lazy import is still a dependency. ``from package import
name`` counts as an import of ``package.name`` when that is a module. The root
package ``cosmos`` (``cosmos/__init__.py``: the version and the Python API's
names, imported on first use) is the facade every import passes through; it
is left out of the graph.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).parents[2] / "cosmos"

LAYERS: list[tuple[str, ...]] = [
    # bottom first: a module may import from its own layer and the layers below it
    # jit: the numba decorator every kernel uses; user_cache: where it and cosmos check keep files;
    # collector: the garbage collector while a command starts up; model_facts: what the model
    # files give a run, kept in the user cache
    (
        "cosmos.errors",
        "cosmos.osc",
        "cosmos.jit",
        "cosmos.user_cache",
        "cosmos.collector",
        "cosmos.model_facts",
    ),
    ("cosmos.rotations", "cosmos.capabilities", "cosmos.robots"),  # robots: the arms, described
    # the hand's vocabulary: which tool, the objects a program declares (no simulator)
    ("cosmos.hand", "cosmos.hand.tool", "cosmos.hand.work_object"),
    ("cosmos.plan",),  # the contract between the language and the executor
    # the language, stage by stage (its vocabulary first, its facade last)
    (
        "cosmos.lang.expressions",
        "cosmos.lang.ast_settings",
        "cosmos.lang.ast_hand",
        "cosmos.lang.ast",
        "cosmos.lang.ast_null_space",
        "cosmos.lang.units",
    ),
    ("cosmos.lang.parse",),
    ("cosmos.lang.check",),
    ("cosmos.lang.evaluate",),
    ("cosmos.lang.compile",),
    ("cosmos.lang",),
    # the arm: the workcell, the plant and the controller's model, the run log the
    # executor writes, obstacles, the servo loop, plan execution
    ("cosmos.hand.gripper_scene", "cosmos.hand.object_scene"),  # the gripper and objects in MJCF
    ("cosmos.workcell",),
    ("cosmos.realism",),  # how the realistic plant differs from the model, and its sensing
    ("cosmos.hand.fingers",),  # the plant's finger drive and pad sensors
    ("cosmos.plant", "cosmos.plant_scene", "cosmos.robot_model"),
    ("cosmos.hand.payload",),  # a held object in the controller's model
    ("cosmos.runlog",),
    ("cosmos.obstacles",),
    ("cosmos.runtime",),
    ("cosmos.hand.grasping",),  # GRASP and RELEASE on the arm
    ("cosmos.execution", "cosmos.hand.supervision", "cosmos.hand.hand_log"),
    ("cosmos.sweep",),  # many runs in varied workcells, on worker processes
    # what people use: a run's results, replay and the REPL, the commands and the Python API
    ("cosmos.replay", "cosmos.repl", "cosmos.run_result", "cosmos.hand.playback_bodies"),
    ("cosmos.commands", "cosmos.api", "cosmos.bench"),
    ("cosmos.cli", "cosmos.__main__"),
]

KNOWN_UPWARD = {
    # (module, what it imports, or a package of it) being removed by other helpers
    # (issue 15, "No arrows up"); delete each line once its imports are gone:
}


def _known(module: str, target: str) -> bool:
    return any(module == m and (target == t or target.startswith(t + ".")) for m, t in KNOWN_UPWARD)


MAX_LINES = 400
# Modules over the limit before the limit was tested (split them, then delete the line).
LONG_MODULES: set[str] = set()


def _modules() -> dict[str, Path]:
    modules = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        if len(parts) > 1:  # the root package is the facade (see the module's docstring)
            modules[".".join(parts)] = path
    return modules


def _imports(modules: dict[str, Path]) -> dict[str, set[str]]:
    """Module -> the cosmos modules it imports (anywhere in its source)."""
    edges: dict[str, set[str]] = defaultdict(set)
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parents = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join(parents + ([node.module] if node.module else []))
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names]
            else:
                continue
            for target in targets:
                while target and target not in modules:
                    target = target.rpartition(".")[0]
                if target.startswith("cosmos") and target != name:
                    edges[name].add(target)
    return edges


def _layer(module: str) -> int:
    """Index in LAYERS of the longest prefix naming ``module``'s layer."""
    best, best_length = -1, -1
    for index, layer in enumerate(LAYERS):
        for prefix in layer:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > best_length:
                best, best_length = index, len(prefix)
    return best


def test_every_module_has_a_layer() -> None:
    """Catches a new top-level module or package that the layer order does not place."""
    assert [m for m in _modules() if _layer(m) < 0] == []


def test_no_import_goes_up_a_layer() -> None:
    """Catches an arrow up: the plan importing the language, a feature package importing the CLI."""
    edges = _imports(_modules())
    upward = sorted(
        (module, target)
        for module, targets in edges.items()
        for target in targets
        if _layer(target) > _layer(module) and not _known(module, target)
    )
    assert upward == []


def test_the_known_upward_imports_are_still_there() -> None:
    """Catches an allow-list entry left behind after its import was removed."""
    edges = _imports(_modules())
    gone = [
        (module, prefix)
        for module, prefix in sorted(KNOWN_UPWARD)
        if not any(t == prefix or t.startswith(prefix + ".") for t in edges.get(module, set()))
    ]
    assert gone == []


def test_no_import_circle() -> None:
    """Catches modules that import each other, directly or round a longer circle
    (the compiler's pass and its handlers sharing a private class did)."""
    edges = _imports(_modules())
    index: dict[str, int] = {}
    lowest: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles: list[list[str]] = []

    def visit(module: str) -> None:  # Tarjan's strongly connected components
        index[module] = lowest[module] = len(index)
        stack.append(module)
        on_stack.add(module)
        for target in sorted(edges.get(module, ())):
            if target not in index:
                visit(target)
                lowest[module] = min(lowest[module], lowest[target])
            elif target in on_stack:
                lowest[module] = min(lowest[module], index[target])
        if lowest[module] == index[module]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == module:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for module in sorted(_modules()):
        if module not in index:
            visit(module)
    assert circles == []


def test_no_module_is_over_400_lines() -> None:
    """Catches a module grown past the house limit (STYLE.md: small modules)."""
    root = PACKAGE.parent
    long = sorted(
        str(path.relative_to(root))
        for path in PACKAGE.rglob("*.py")
        if len(path.read_text(encoding="utf-8").splitlines()) > MAX_LINES
    )
    assert [path for path in long if path not in LONG_MODULES] == []
    assert [path for path in sorted(LONG_MODULES) if path not in long] == [], "allow-listed but short now"
