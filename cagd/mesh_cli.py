"""``cagd mesh FILE.step -o out.stl [--tol T] [--ascii]``: every face of a STEP/IGES file
meshed within chordal ``tol`` into one STL (or OBJ for a ``.obj`` output). Exit codes:
0 done (within tol), 1 written but tol not met at the density cap, 2 bad input."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from .errors import CagdError


def add_parser(sub: Any) -> None:
    p = sub.add_parser("mesh", help="every face of a STEP/IGES file to an STL or OBJ mesh")
    p.add_argument("model", type=Path, help="the STEP or IGES file")
    p.add_argument("-o", "--output", type=Path, required=True, help="the .stl or .obj file to write")
    p.add_argument("--tol", type=float, default=0.1,
                   help="chordal tolerance, a distance in model units (0.1, as FreeCAD's standard mesher)")
    p.add_argument("--ascii", action="store_true", help="ASCII STL instead of binary")


def run_mesh(args: argparse.Namespace) -> int:
    from . import occ
    from .mesh import write_obj, write_stl
    if args.model.suffix.lower() not in occ.files.STEP_SUFFIXES + occ.files.IGES_SUFFIXES:
        raise CagdError(f"model: {str(args.model)!r} is not a .step/.stp/.iges/.igs file")   # the argument's name
    contents = occ.read_cad(args.model)
    from .surfaces.base import Surface
    from .surfaces.trimmed import TrimmedSurface
    faces = [item.object for item in contents if isinstance(item.object, (Surface, TrimmedSurface))]
    if not faces:
        raise CagdError(f"model: {str(args.model)!r} has no faces to mesh")
    if args.output.suffix.lower() == ".obj":
        res = write_obj(args.output, faces, tol=args.tol)
    else:
        res = write_stl(args.output, faces, tol=args.tol, binary=not args.ascii)
    print(f"{args.output}: {len(faces)} faces, {len(res.triangles)} triangles; {res.message}")
    return 0 if res.converged else 1
