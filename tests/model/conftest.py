"""Makes ``model_cases.py`` (the shared valid-entry table) importable from this folder's tests."""
import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
