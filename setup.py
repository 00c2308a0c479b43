"""Package layout (metadata and dependencies are in setup.cfg).

The FreeCAD addon lives in the checkout's ``workbench/`` folder and ships as package
data ``cagd/freecad/addon`` (``cagd-freecad install`` puts it into FreeCAD).
"""
from setuptools import find_packages, setup

setup(
    packages=find_packages(include=["cagd", "cagd.*", "cq_ext", "cq_ext.*"])
    + ["cagd.freecad.addon", "cagd.freecad.addon.cagdwb"],
    package_dir={"cagd.freecad.addon": "workbench"},
    package_data={"cagd.model": ["*.json"], "cagd.freecad.addon": ["*.xml", "*.md", "icons/*.svg"]},
)
