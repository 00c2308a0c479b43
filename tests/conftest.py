"""Test configuration: makes ``tests/strategies.py`` importable as ``strategies``
from every test directory (the test dirs have no ``__init__.py``)."""
import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)

# CI runs the property tests derandomized (the same examples every run, so a red CI
# is reproducible); local runs explore new examples each time.
from hypothesis import settings as _settings  # noqa: E402

_settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
if os.environ.get("CI"):
    _settings.load_profile("ci")
