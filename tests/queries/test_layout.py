"""The layout of cagd.queries (issue 16): result types in one module, no import circle
between the intersection modules, tolerances named (no bare 1e-* literals in code)."""
import ast
import io
import re
import tokenize
from pathlib import Path

import cagd.queries as q
from cagd.queries import results

PACKAGE = Path(q.__file__).parent
NAMED = re.compile(r"^_?[A-Z][A-Z0-9_]*\s*(:[^=]*)?=")      # a module-level NAME = value line


def _imports(path: Path):
    """(module, level) of every import in a file (nested ones included)."""
    tree = ast.parse(path.read_text())
    return {(n.module or "", n.level) for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}


def test_result_types_live_in_results():
    for name in ("ClosestPoints", "Deviation", "DistanceResult", "IntersectionPoint", "IntersectionResult",
                 "Overlap", "IntersectionCurve", "SurfaceOverlap"):
        assert getattr(q, name) is getattr(results, name)
        assert getattr(q, name).__module__ == "cagd.queries.results"


def test_no_circle_between_intersect_modules():
    # intersect dispatches to intersect_surfaces and the point solver; neither imports it back
    for module in ("intersect_surfaces.py", "_point_solver.py", "_marching.py", "_branch_fit.py", "results.py"):
        assert ("intersect", 1) not in _imports(PACKAGE / module), module


def bare_literals(source: str):
    """The ``1e-*`` number literals of a source outside module-level named constants."""
    lines = source.splitlines()
    out = []
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.NUMBER and re.search(r"e-\d", tok.string.lower()) \
                and not NAMED.match(lines[tok.start[0] - 1]):
            out.append((tok.start[0], tok.string))
    return out


def test_bare_literal_scan_finds_them():
    assert bare_literals("X = 1e-9\n\ndef f(a):\n    return a > 1e-12\n") == [(4, "1e-12")]


def test_no_bare_tolerances_in_queries():
    found = {p.name: bare_literals(p.read_text()) for p in sorted(PACKAGE.glob("*.py"))}
    assert {k: v for k, v in found.items() if v} == {}
