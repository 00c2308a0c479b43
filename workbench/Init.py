# FreeCAD runs this file (exec, no __file__) at start-up, with this folder on sys.path.
# It only makes the engine importable; the objects live in the cagdwb package.
try:
    import cagdwb as _cagdwb
    _cagdwb.ensure_engine()
except ImportError as _exc:
    import FreeCAD as _App
    _App.Console.PrintError(f"cagd workbench: {_exc}\n")
