"""The second half of ``cagd demo``: the built-in model (cagd/model/default.json: the
seed ellipsoid as a closed solid, a bicubic Bezier patch, a natural-spline profile
revolved into a solid, a Bezier triangle, a Coons patch, a G2-joined curve pair)
to STEP and IGES, a PNG of each object with its control net (and curvature comb
for curves), and the round-trip report (report.md)."""
from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Dict, Optional, TextIO

import numpy as np

if TYPE_CHECKING:                       # cagd.occ needs OCP: imported where it runs
    from .model.loader import Entry
    from .occ.export import ExportResult


def _net(obj):
    """The control net to draw: the object's own points (triangles: their flat net)."""
    pts = np.asarray(obj.control_points if not isinstance(obj.control_points, dict)
                     else list(obj.control_points.values()), dtype=float)
    return pts


def plot_entry(entry: Entry, path: Path) -> Path:
    """One PNG per model entry: curves with control polygon and curvature comb (xy view),
    surfaces shaded with their control nets."""
    from .plotting import plot_curves, plot_surfaces
    title = f"{entry.name} ({entry.type})"
    if entry.kind == "curve":
        curves = entry.objects
        polys = [c.to_nurbs().control_points for c in curves]
        return plot_curves(path, title, curves, polys)
    nets = []
    for s in entry.objects:
        net = getattr(s, "control_points", None)
        if net is None or np.ndim(net) not in (2, 3):
            net = s.to_nurbs().control_points
        nets.append(np.asarray(net, dtype=float))
    return plot_surfaces(path, title, entry.objects, nets)


def run_model_demo(out_dir: Path, stream: Optional[TextIO] = None, plots: bool = True) -> ExportResult:
    """Export the default model to out_dir/model.step and model.igs, write report.md
    and the PNGs; print the summary; return the :class:`cagd.occ.export.ExportResult`."""
    from .model import default_model
    from .occ.export import export_model
    stream = sys.stdout if stream is None else stream
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    model = default_model()
    result = export_model(model, out_dir / "model.step", out_dir / "model.igs")
    (out_dir / "report.md").write_text(result.to_markdown())
    if plots:
        for k, entry in enumerate(model.entries, 1):
            plot_entry(entry, out_dir / f"model_{k:02d}_{entry.name}.png")
    print("", file=stream)
    print(f"built-in model {result.model_name!r}: {len(model.exported())} items to {out_dir / 'model.step'} "
          f"and {out_dir / 'model.igs'}", file=stream)
    for s in result.solids:
        print(f"  solid {s.name}: {s.faces} faces, valid {s.valid}, volume OCCT {s.volume_occt:.10g}, "
              f"engine {abs(s.volume_engine):.10g} (relative difference {s.relative_difference:.1e})"
              + ("" if s.volume_exact is None else
                 f", closed form {s.volume_exact:.10g} (engine off by {s.exact_difference:.1e})"), file=stream)
    worst: Dict[str, float] = {}
    for r in result.reports:
        for st in r.stages:
            worst[st.stage] = max(worst.get(st.stage, 0.0), st.max_deviation)
    print("  round trip, worst relative deviation over all objects: "
          + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()), file=stream)
    for f, n, fa, ed in result.read_back:
        print(f"  {f} read back: {fa} faces, {ed} free curves (expected {result.expected[0]}, {result.expected[1]})",
              file=stream)
    print(f"  report: {out_dir / 'report.md'}; verdict: {'all checks passed' if result.passed else 'FAILED'}",
          file=stream)
    return result
