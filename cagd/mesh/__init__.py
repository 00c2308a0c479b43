"""Triangle meshes of surfaces for STL/OBJ export (issue 15)."""
from .export import MeshResult, mesh, write_obj, write_stl

__all__ = ["MeshResult", "mesh", "write_obj", "write_stl"]
