"""PEP 517 build backend of the analysis package: setuptools' own (setuptools.build_meta),
reached offline.

pip builds in an isolated environment that hides the system's site-packages and installs the
backend's requirements from an index; offline there is none, so `pip install -e analysis`
would fail although Debian's python3-setuptools and python3-wheel are installed. This file
(pyproject.toml: requires = [], backend-path = ["_build"]) needs nothing installed into that
environment: it puts the base interpreter's site-packages back on the path, imports
setuptools from there, and asks for no further requirements.
"""
import site
import sys

try:
    import setuptools.build_meta as _backend
except ImportError:
    sys.path.extend(p for p in site.getsitepackages([sys.base_prefix]) if p not in sys.path)
    import setuptools.build_meta as _backend

build_wheel = _backend.build_wheel
build_sdist = _backend.build_sdist
build_editable = _backend.build_editable
prepare_metadata_for_build_wheel = _backend.prepare_metadata_for_build_wheel
prepare_metadata_for_build_editable = _backend.prepare_metadata_for_build_editable


# setuptools asks for `wheel` from the index; Debian's python3-wheel is already on the path.
def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_editable(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []
