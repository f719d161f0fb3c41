"""The one table of motion parameters: each is stated here once.

:func:`a2b.motion` checks names against it, the command line builds its options from it
(``--delta``, ``--m`` …), the readers take the keys of a ``parameters`` mapping by its kinds,
and ``describe`` reports the parameter a motion was solved from by its name. Free of numpy,
so that ``a2b --help`` stays light.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass


@dataclass(frozen=True)
class Parameter:
    """A motion parameter.

    Attributes
    ----------
    name : str
        The keyword of :func:`a2b.motion` and the key in a poses or jobs file; the option is
        ``--name`` with ``-`` for ``_``.
    mode : str
        The mode that takes it.
    kind : str
        ``number``, ``branch`` (+1 or −1), ``bool``, ``pose`` (a 4x4 matrix), ``frame`` (a
        name), or ``vector`` (``size`` numbers).
    unit : str
        What a number measures: ``length``, ``radian``, ``length per radian`` or ``""``.
    help : str
        One line for ``--help``.
    excludes : tuple of str
        The parameters that choose the same thing: at most one of a group is given.
    size : int
        The count of numbers of a ``vector``.
    components : str
        The names of a vector's numbers, for messages.
    off : str
        A ``bool``'s name when false, as an option (``--short-way``).
    """

    name: str
    mode: str
    kind: str
    unit: str
    help: str
    excludes: tuple = ()
    size: int = 0
    components: str = ""
    off: str = ""

    @property
    def trailing(self) -> int:
        """Array dimensions of the parameter of one motion (0 for a number)."""
        return {"vector": 1, "pose": 2}.get(self.kind, 0)


#: The motions :func:`a2b.motion` builds, each a class in :data:`a2b.motions.REGISTRY`.
MODES = ("darboux", "cubic", "screw")

#: δ's group: the ways to choose the one essential parameter of a Darboux motion.
SOLVERS = ("delta", "kappa", "lam", "pitch_start", "pitch_end", "through")


def _solver(name, kind, unit, help_):
    return Parameter(name, "darboux", kind, unit, help_, tuple(s for s in SOLVERS if s != name))


TABLE = (
    _solver("delta", "number", "length", "the fiber offset δ = sB − sA, a length (default 0)."),
    _solver(
        "kappa",
        "number",
        "radian",
        "the phase κ of the transmission curve z = z0 + λ sin(ω + κ), radians.",
    ),
    _solver(
        "lam",
        "number",
        "length",
        "the amplitude λ of the transmission curve (two solutions: see --branch).",
    ),
    Parameter("branch", "darboux", "branch", "", "which of the two solutions for --lam, +1 or -1."),
    _solver(
        "pitch_start",
        "number",
        "length per radian",
        "the pitch dz/dω at the start, length per radian.",
    ),
    _solver(
        "pitch_end", "number", "length per radian", "the pitch dz/dω at the end, length per radian."
    ),
    _solver("through", "pose", "", "a file with a third pose the motion passes through."),
    Parameter(
        "long_way",
        "darboux",
        "bool",
        "",
        "go the long way round (the other sign of the end pose's Study vector).",
        off="short_way",
    ),
    Parameter(
        "m",
        "cubic",
        "vector",
        "",
        "the vector m of μ_[m], e.g. 1,0,0,0.5.",
        size=4,
        components="m0, m1, m2, m3",
    ),
    Parameter(
        "alpha",
        "cubic",
        "vector",
        "",
        "fiber coordinates α of the start pose in the kernel basis.",
        ("a",),
        6,
        "α0 … α5",
    ),
    Parameter(
        "beta",
        "cubic",
        "vector",
        "",
        "fiber coordinates β of the end pose in the kernel basis.",
        ("b",),
        6,
        "β0 … β5",
    ),
    Parameter(
        "a", "cubic", "number", "", "the essential scalar a (instead of --alpha).", ("alpha",)
    ),
    Parameter("b", "cubic", "number", "", "the essential scalar b (instead of --beta).", ("beta",)),
    Parameter(
        "frame",
        "cubic",
        "frame",
        "",
        "construct in the canonical frame of the two poses (default) or apply μ_[m] in the "
        "given coordinates.",
    ),
)

BY_NAME = {p.name: p for p in TABLE}

#: mode -> the names of its parameters, in the table's order.
OF_MODE = {mode: tuple(p.name for p in TABLE if p.mode == mode) for mode in MODES}

#: Groups of parameters that choose the same thing (a command-line option drops the file's
#: others of its group). ``branch`` goes with ``lam``: it is dropped with the δ group.
EXCLUSIVE = (
    frozenset(SOLVERS) | {"branch"},
    frozenset({"alpha", "a"}),
    frozenset({"beta", "b"}),
)


#: An angle in degrees, as options and files accept it where radians are asked for: ``45deg``.
_DEGREES = re.compile(
    r"\s*([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?)\s*deg\s*", re.ASCII
)


def degrees(text: str) -> float | None:
    """The radians of an angle written in degrees (``"45deg"``, ``"-90 deg"``), else None."""
    match = _DEGREES.fullmatch(text)
    return None if match is None else math.radians(float(match.group(1)))
