"""``python -m cagd.freecad install|uninstall [--copy] [--mod-dir DIR]``."""
import sys

from .install import main

sys.exit(main())
