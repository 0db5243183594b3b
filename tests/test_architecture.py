"""The layout's rules, read from the source: the packages' layering, no import circle, no library package importing
the CLI, a toolkit that knows no problem, one construction path per model family, no facades."""

import ast
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[1]
# The layering, lowest first: a module imports only modules of its own package or of a package before it.
PACKAGES = ("bifurcation", "axles", "reduced_model", "mbs_shimmy", "comparisons")


def modules() -> dict[str, pathlib.Path]:
    found = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            found[name] = path
    return found


def import_graph() -> dict[str, set[str]]:
    """Every import of a project module by a project module, the ones inside functions included."""
    mods = modules()
    graph = {}
    for name, path in mods.items():
        targets = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module and not node.level:
                candidates = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                candidates = [a.name for a in node.names]
            else:
                continue
            targets |= {c for c in candidates if c in mods and c != name}
        graph[name] = targets
    return graph


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's algorithm: the components with more than one module are the import circles."""
    index, low, stack, on_stack, circles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in graph:
        if v not in index:
            visit(v)
    return circles


def test_the_import_graph_has_no_circle():
    assert strongly_connected(import_graph()) == []


def test_no_library_package_imports_the_command_line():
    offenders = {m: sorted(t for t in targets if t.startswith("comparisons.cli"))
                 for m, targets in import_graph().items() if not m.startswith("comparisons.cli")}
    assert {m: t for m, t in offenders.items() if t} == {}


def test_the_toolkit_imports_nothing_of_the_models():
    graph = import_graph()
    toolkit = {m: targets for m, targets in graph.items() if m.split(".")[0] == "bifurcation"}
    assert toolkit, "the toolkit package is missing"
    outside = {m: sorted(t for t in targets if t.split(".")[0] != "bifurcation")
               for m, targets in toolkit.items()}
    assert {m: t for m, t in outside.items() if t} == {}


def test_the_packages_are_layered():
    """bifurcation <- axles <- reduced_model <- mbs_shimmy <- comparisons: no import runs up the stack."""
    rank = {package: k for k, package in enumerate(PACKAGES)}
    upward = {m: sorted(t for t in targets if rank[t.split(".")[0]] > rank[m.split(".")[0]])
              for m, targets in import_graph().items()}
    assert {m: t for m, t in upward.items() if t} == {}


def test_each_package_is_where_the_layout_says():
    for package in PACKAGES:
        assert (ROOT / package / "__init__.py").is_file(), package
    # the toolkit is no longer inside the paper's model, the studies over both models not inside the MBS
    assert not (ROOT / "reduced_model" / "bifurcation").exists()
    assert not any((ROOT / "mbs_shimmy" / f"{m}.py").exists()
                   for m in ("kick", "cycle_peak", "limit_cycle", "growth", "assumption_study", "dimensions"))


# The model families and the one module allowed to construct each.
FAMILY_FACTORIES = {"SpeedFamily": "comparisons/api.py", "MbsFamily": "comparisons/api.py"}


def _library_sources():
    for folder in PACKAGES + ("tools",):
        for path in (ROOT / folder).rglob("*.py"):
            yield path, ast.parse(path.read_text())


def test_families_are_constructed_by_their_factory_only():
    found = sorted(f"{path.relative_to(ROOT)}:{node.lineno}: {node.func.id}(...)"
                   for path, tree in _library_sources() for node in ast.walk(tree)
                   if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                   and node.func.id in FAMILY_FACTORIES
                   and str(path.relative_to(ROOT)) != FAMILY_FACTORIES[node.func.id])
    assert found == []


def test_no_parsed_namespace_is_written_outside_the_parser():
    """``args.x = ...`` turns the parsed command line into a cache: only the parser module may set attributes of
    an argparse Namespace (the commands read them)."""
    parser_module = ROOT / "comparisons" / "cli" / "main.py"
    found = sorted(f"{path.relative_to(ROOT)}:{node.lineno}"
                   for path, tree in _library_sources() if path != parser_module for node in ast.walk(tree)
                   if isinstance(node, (ast.Assign, ast.AugAssign))
                   for target in (node.targets if isinstance(node, ast.Assign) else [node.target])
                   if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name)
                   and target.value.id == "args")
    found += sorted(f"{path.relative_to(ROOT)}:{node.lineno}: setattr"
                    for path, tree in _library_sources() if path != parser_module for node in ast.walk(tree)
                    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "setattr"
                    and node.args and isinstance(node.args[0], ast.Name) and node.args[0].id == "args")
    assert found == []


def test_no_module_level_getattr_facade():
    facades = [name for name, path in modules().items()
               if any(isinstance(n, ast.FunctionDef) and n.name == "__getattr__" for n in ast.parse(path.read_text()).body)]
    assert facades == []


# A word of the shimmy problem inside an identifier or a sentence; ``_`` and digits count as word boundaries, so
# ``speed_derivative``, ``SPEED_SCALE`` and ``seed_speeds`` are caught as well as "speed" in a docstring.
PROBLEM_WORDS = re.compile(r"(?<![a-z])(speeds?|v_?min|v_?max|kmh)(?![a-z])|km/h", re.IGNORECASE)


def test_the_pattern_of_problem_words_finds_them():
    for text in ("speed", "A(V) with V the Speed", "speed_derivative", "SPEED_SCALE", "seed_speeds", "vmin", "v_max",
                 "clip(vmax)", "400 km/h", "to_kmh"):
        assert PROBLEM_WORDS.search(text), text
    for text in ("p_min, p_max", "speedup", "primary_min", "v_lo", "the primary parameter p"):
        assert not PROBLEM_WORDS.search(text), text


def test_the_toolkit_names_no_speed():
    """The toolkit continues in a named first parameter p, whatever it means to the problem: no identifier,
    comment or docstring under ``bifurcation/`` says speed, vmin/vmax or km/h."""
    found = [f"{path.relative_to(ROOT)}:{n}: {line.strip()}"
             for path in sorted((ROOT / "bifurcation").rglob("*.py"))
             for n, line in enumerate(path.read_text().splitlines(), 1) if PROBLEM_WORDS.search(line)]
    assert found == []


# The speed's old letter in the toolkit (V, V0, A_V, hV, V_H, "(V, q)") and state counts in comments ("(8,)").
SPEED_LETTER = re.compile(r"(?<![A-Za-z0-9])V(?![A-Za-z])|(?<=[a-z_])V(?![A-Za-z])|\(\d+,\)")


def test_the_pattern_of_the_speed_letter_finds_it():
    for text in ("V", "A(V)", "V0", "V_H", "A_V", "hV", "col_V", "(V, q)", "# (8,) max"):
        assert SPEED_LETTER.search(text), text
    for text in ("SVD", "VECTOR_WEIGHT", "p, q", "A_p", "(n,)", "(N, m + 1, n)", "ODE"):
        assert not SPEED_LETTER.search(text), text


def test_the_toolkit_calls_its_first_parameter_p():
    """The primary parameter is p in names, comments and docstrings under ``bifurcation/``, and arrays are sized
    by n, not by the axle's state count."""
    found = [f"{path.relative_to(ROOT)}:{n}: {line.strip()}"
             for path in sorted((ROOT / "bifurcation").rglob("*.py"))
             for n, line in enumerate(path.read_text().splitlines(), 1) if SPEED_LETTER.search(line)]
    assert found == []


def test_the_models_import_nothing_of_the_comparisons():
    offenders = {m: sorted(t for t in targets if t.split(".")[0] == "comparisons")
                 for m, targets in import_graph().items() if m.split(".")[0] != "comparisons"}
    assert {m: t for m, t in offenders.items() if t} == {}


def _sources():
    for folder in PACKAGES + ("tools", "tests"):
        for path in (ROOT / folder).rglob("*.py"):
            yield path, ast.parse(path.read_text())


def test_speeds_are_converted_in_the_units_module_only():
    # a km/h conversion written by hand: a product or quotient with the literal 3.6
    found = sorted({str(path.relative_to(ROOT)) for path, tree in _sources() for node in ast.walk(tree)
                    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Mult, ast.Div))
                    and any(isinstance(o, ast.Constant) and o.value == 3.6 for o in (node.left, node.right))})
    assert found == []


def test_library_code_chooses_no_matplotlib_backend():
    found = sorted({str(path.relative_to(ROOT)) for path, tree in _sources() for node in ast.walk(tree)
                    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "use"
                    and isinstance(node.func.value, ast.Name) and node.func.value.id == "matplotlib"
                    and not path.is_relative_to(ROOT / "tests")})
    assert found == []


def test_no_regex_reads_messages():
    """Messages carry their values by name (``bifurcation.messages``): no library module reads numbers or names back
    out of a message with a regular expression (the interface once rewrote "speed = 41.67" into km/h that way, and
    the axle-file reader found the entries a consistency error named by splitting its words).  A library's own
    exception text (tomllib's line number before Python 3.14) is not ours to structure."""
    found = sorted(f"{path.relative_to(ROOT)}:{node.lineno}"
                   for path, tree in _library_sources() for node in ast.walk(tree)
                   if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                   and isinstance(node.func.value, ast.Name) and node.func.value.id == "re"
                   and any(re.search(r"message", ast.unparse(a)) for a in node.args[1:]))
    assert found == []


def test_the_toolkit_results_carry_structured_messages():
    import typing

    from bifurcation.continuation import Branch, Stop
    from bifurcation.cycle_curves.result import CycleCurve
    from bifurcation.cycles.problem import CycleBranch
    from bifurcation.equilibria.hopf_curves import HopfCurve
    from bifurcation.messages import Message
    from reduced_model.trajectory import Trajectory
    for cls, name in ((Branch, "message"), (Stop, "message"), (CycleBranch, "message"), (Trajectory, "message")):
        assert typing.get_type_hints(cls)[name] is Message, cls
    for cls in (HopfCurve, CycleCurve):
        assert typing.get_type_hints(cls)["messages"] == tuple[Message, Message], cls
