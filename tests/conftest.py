"""Test configuration: makes ``tests/strategies.py`` importable as ``strategies``
from every test directory (the test dirs have no ``__init__.py``)."""
import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
