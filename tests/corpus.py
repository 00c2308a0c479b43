"""Where the real CAD files are: ``CAD``, ../shared/data/cad beside the checkout, else beside
the main checkout (/work/shared/data/cad) for a clone or worktree elsewhere, else the path
beside the checkout, absent: the tests that read it skip then. The project never reads it
at run time (its users do not have it)."""
from pathlib import Path

_BESIDE = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "cad"
CAD = next((p for p in (_BESIDE, Path("/work/shared/data/cad")) if p.is_dir()), _BESIDE)
