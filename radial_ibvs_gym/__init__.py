"""radial_ibvs_gym: visual servoing of mobile robots with (non-)central catadioptric cameras.

Implements Aliakbarpour, Tahri and Araujo, "Visual servoing of mobile robots using non-central
catadioptric cameras", Robotics and Autonomous Systems, 2014.

Layers (imports flow one way): ``config`` -> ``geometry`` -> ``camera`` -> ``features`` ->
``vision`` -> ``physics`` -> ``scenarios`` -> ``envs``. The maths layers load numpy and nothing
heavier: ``import radial_ibvs_gym.camera`` loads neither Gymnasium nor the simulator.

The environments are registered with Gymnasium on ``import radial_ibvs_gym``, by entry-point
strings (:mod:`radial_ibvs_gym.registration`). If Gymnasium is not imported yet, the
registration waits for it: it runs as soon as Gymnasium's own import finishes, so both
``import radial_ibvs_gym; import gymnasium`` and the other order work, and a user of the maths
alone never pays for Gymnasium.
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys
from collections.abc import Sequence
from types import ModuleType
from typing import Any


def _version() -> str:
    """Return the installed distribution's version (``pyproject.toml`` is its one source)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("radial_ibvs_gym")
    except PackageNotFoundError:  # a source tree on sys.path, never installed
        return "0+unknown"


__version__ = _version()

__all__ = ["__version__"]


def _register() -> None:
    from radial_ibvs_gym.registration import register_envs

    register_envs()


class _RegisterAfterGymnasium(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """A one-shot import hook: lets ``gymnasium`` import as usual, then registers the envs."""

    def __init__(self) -> None:
        self._loader: Any = None

    def find_spec(
        self, fullname: str, path: Sequence[str] | None, target: ModuleType | None = None
    ) -> importlib.machinery.ModuleSpec | None:
        if fullname != "gymnasium":
            return None
        # not removed here: importlib.util.find_spec("gymnasium") (TorchRL's check that it is
        # installed) asks for a spec without importing; the hook goes once Gymnasium has run
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is None or spec.loader is None:
            return spec  # not installed: the import fails as it would without the hook
        self._loader = spec.loader
        spec.loader = self
        return spec

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType | None:
        return self._loader.create_module(spec)

    def exec_module(self, module: ModuleType) -> None:
        self.remove()
        module.__loader__ = module.__spec__.loader = self._loader  # type: ignore[union-attr]
        self._loader.exec_module(module)
        _register()

    def remove(self) -> None:
        if self in sys.meta_path:
            sys.meta_path.remove(self)


if "gymnasium" in sys.modules:
    _register()
elif not any(isinstance(f, _RegisterAfterGymnasium) for f in sys.meta_path):
    sys.meta_path.insert(0, _RegisterAfterGymnasium())
