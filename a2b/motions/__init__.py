"""The motions, one module per mode, and :data:`REGISTRY`, the one table of modes.

A mode is a :class:`~a2b.motions.base.Motion` subclass that carries its own behaviour: its
``mode`` name and ``description``, how it is built from the parameters of
:mod:`a2b.parameters` (``from_parameters``), its closed-form transmission curve
(``transmission``, ``transmission_form``), its family of curves through A and B (``family``,
``family_kinds``) and the one-line summary of the figures (``summary``). :func:`a2b.motion`,
``a2b describe``, ``a2b plot`` and ``a2b view`` ask the class, never the name.

Adding a mode touches three files: its module here, one entry in :data:`REGISTRY`, and its
name and parameters in :mod:`a2b.parameters` (``MODES``, ``TABLE``).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..parameters import MODES, OF_MODE
from .base import Motion
from .cubic import CubicMotion
from .darboux import DarbouxMotion
from .screw import ScrewMotion


@dataclass(frozen=True)
class Mode:
    """A mode of :func:`a2b.motion`: its name, its class and its parameters."""

    name: str
    motion: type[Motion]

    @property
    def parameters(self) -> tuple[str, ...]:
        """The names of its parameters, in the order of :data:`a2b.parameters.TABLE`."""
        return OF_MODE[self.name]

    @property
    def description(self) -> str:
        return self.motion.description


#: mode name -> :class:`Mode`, in the order of :data:`a2b.parameters.MODES`.
REGISTRY = {cls.mode: Mode(cls.mode, cls) for cls in (DarbouxMotion, CubicMotion, ScrewMotion)}
REGISTRY = {name: REGISTRY[name] for name in MODES}

__all__ = ["Mode", "REGISTRY"]
