"""TF as a tree: the pose of a child frame in a parent frame, composed through the links between.

Transforms are records ``parent → child`` with a stamp, a quaternion and a translation, as any
container decodes them (ROS 2 ``tf2_msgs/TFMessage`` in MCAP or a rosbag2, Foxglove's
``FrameTransform``): :class:`TransformRecords`. Each child frame has one parent; the links
from ``child`` up to ``parent`` form the chain, and the pose of ``child`` in ``parent`` is the
product of the link transforms from the parent down,

.. math::

   T_{\\mathrm{parent}}^{\\mathrm{child}}(t) = T_{f_0}^{f_1}(t)\\, T_{f_1}^{f_2}(t) \\cdots
   T_{f_{m-1}}^{f_m}(t), \\qquad f_0 = \\mathrm{parent},\\ f_m = \\mathrm{child}.

A static link (``/tf_static``) is latched: its last transform holds at every time. A dynamic
link is sampled at time ``t`` by a :class:`a2b.resample.Resampler` of its own stamps, with the
motion the caller chooses (ScLERP, ``screw``, by default); a time equal to a stamp is that
transform exactly. The poses are given at the stamps of the dynamic link nearest the child
(tf2 looks frames up at the stamp of the data); every other dynamic link must have transforms
at or around each of them: a2b does not extrapolate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputFileError, listing, printable, quoted

__all__ = ["TF_STATIC", "Link", "TransformRecords", "chain", "compose", "compose_topics"]

#: The topic of latched transforms (ROS 2's ``tf2_ros`` static broadcaster).
TF_STATIC = "/tf_static"


@dataclass
class TransformRecords:
    """Decoded transforms, one row each: ``parents`` and ``children`` (frame names, str),
    ``times (N,)`` s, ``quat_wxyz (N, 4)``, ``translations (N, 3)`` (the child frame's origin
    and axes in the parent frame), ``static (N,)`` True for a latched (``/tf_static``) one."""

    parents: np.ndarray
    children: np.ndarray
    times: np.ndarray
    quat_wxyz: np.ndarray
    translations: np.ndarray
    static: np.ndarray

    @classmethod
    def joined(cls, parts: list) -> TransformRecords:
        """The records of ``parts`` one after the other."""
        if not parts:
            empty = np.empty(0, object)
            return cls(empty, empty, np.empty(0), np.empty((0, 4)), np.empty((0, 3)),
                       np.empty(0, bool))  # fmt: skip
        fields = ("parents", "children", "times", "quat_wxyz", "translations", "static")
        return cls(*(np.concatenate([getattr(part, f) for part in parts]) for f in fields))


@dataclass
class Link:
    """One link ``parent → child`` of a chain: its transforms in time order (a static link:
    its last one)."""

    parent: str
    child: str
    static: bool
    times: np.ndarray
    quat_wxyz: np.ndarray
    translations: np.ndarray

    def __str__(self) -> str:
        return f"{printable(self.parent)}→{printable(self.child)}"


def chain(records: TransformRecords, parent: str, child: str, where: str) -> list[Link]:
    """The links from ``parent`` down to ``child``, in that order.

    Raises
    ------
    InputFileError
        If a frame on the way has two parents, a link is both static and dynamic, a dynamic
        link repeats a stamp, or the chain from ``child`` up ends before ``parent``.
    """
    links: list[Link] = []
    frame, seen = child, {child}
    while frame != parent:
        mine = np.flatnonzero(records.children == frame)
        parents = sorted(set(records.parents[mine].tolist()))
        if not parents:
            path = " → ".join(quoted(f) for f in [frame, *reversed([lk.child for lk in links])])
            known = sorted(set(records.children.tolist()) | set(records.parents.tolist()))
            raise InputFileError(
                f"{where}: no transform to the frame {quoted(frame)}, so no chain from "
                f"{quoted(parent)} to {quoted(child)} (found up to {path}; the frames are "
                f"{listing(map(printable, known)) or 'none'})"
            )
        if len(parents) > 1:
            raise InputFileError(
                f"{where}: the frame {quoted(frame)} has two parents, "
                f"{listing(map(printable, parents))}; "
                "a TF tree gives each frame one"
            )
        links.append(_link(records, mine, parents[0], frame, where))
        frame = parents[0]
        if frame in seen:
            raise InputFileError(f"{where}: the frames loop at {quoted(frame)}")
        seen.add(frame)
    return links[::-1]


def _link(records: TransformRecords, rows: np.ndarray, parent: str, child: str, where: str):
    static = records.static[rows]
    name = f"{quoted(parent)}→{quoted(child)}"
    if static.any() and not static.all():
        raise InputFileError(f"{where}: the link {name} is both static and dynamic")
    if static.all():
        last = rows[-1:]
        return Link(parent, child, True, records.times[last], records.quat_wxyz[last],
                    records.translations[last])  # fmt: skip
    order = rows[np.argsort(records.times[rows], kind="stable")]
    times = records.times[order]
    repeated = np.flatnonzero(np.diff(times) == 0)
    if len(repeated):
        raise InputFileError(
            f"{where}: the link {name} has two transforms at {float(times[repeated[0]])!r} s"
        )
    return Link(parent, child, False, times, records.quat_wxyz[order],
                records.translations[order])  # fmt: skip


def compose(
    records: TransformRecords,
    parent: str,
    child: str,
    where: str,
    mode: str = "screw",
    **parameters,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """The poses of ``child`` in ``parent`` (see the module): ``(times, quat_wxyz (M, 4),
    translations (M, 3), statement)``, ``statement`` a line that says the chain for ``-v``.

    ``mode`` and ``parameters`` are the motion of each dynamic link between its stamps
    (:class:`a2b.resample.Resampler`). ``where`` starts every error message.

    Raises
    ------
    InputFileError
        As :func:`chain`; and when a dynamic link has no transform at or before the first
        stamp, or at or after the last.
    """
    from ..poses import matrices_from_quat_trans, quat_trans_from_matrices

    links = chain(records, parent, child, where)
    if not links:
        raise InputFileError(f"{where}: --input-frame and --input-child-frame are one frame")
    dynamic = [link for link in links if not link.static]
    stamps = dynamic[-1] if dynamic else max(links, key=lambda link: float(link.times[-1]))
    times = stamps.times
    product = np.broadcast_to(np.eye(4), (len(times), 4, 4))
    for link in links:
        if link.static or link is stamps:
            matrices = matrices_from_quat_trans(link.quat_wxyz, link.translations)
        else:
            matrices = _sampled(link, stamps, mode, parameters, where)
        product = product @ matrices
    if len(links) == 1:
        quat, trans = stamps.quat_wxyz, stamps.translations  # as the file holds them
    else:
        quat, trans = quat_trans_from_matrices(product)
    kinds = ", ".join(f"{link} {'static' if link.static else 'dynamic'}" for link in links)
    statement = (
        f"TF chain {' → '.join(printable(f) for f in [parent] + [lk.child for lk in links])} "
        f"({kinds}): "
        f"{len(times)} poses at the stamps of {stamps}"
        + (f", the other dynamic links by {mode} between their stamps" if len(dynamic) > 1 else "")
    )
    return times, quat, trans, statement


def _sampled(link: Link, stamps: Link, mode: str, parameters: dict, where: str) -> np.ndarray:
    """The matrices of dynamic ``link`` at the stamps of ``stamps``."""
    from ..resample import Resampler

    times = stamps.times
    for side, bad, edge in (
        ("before", times[0] < link.times[0], times[0]),
        ("after", times[-1] > link.times[-1], times[-1]),
    ):
        if bad:
            raise InputFileError(
                f"{where}: no transform {quoted(link.parent)}→{quoted(link.child)} at or {side} "
                f"{float(edge)!r} s, the {'first' if side == 'before' else 'last'} stamp of "
                f"{quoted(stamps.parent)}→{quoted(stamps.child)} (its transforms run from "
                f"{float(link.times[0])!r} to {float(link.times[-1])!r} s)"
            )
    if len(link.times) == 1:  # every stamp is its one stamp
        from ..poses import matrices_from_quat_trans

        one = matrices_from_quat_trans(link.quat_wxyz, link.translations)
        return np.broadcast_to(one, (len(times), 4, 4))
    resampler = Resampler(link.times, mode=mode, quat_wxyz=link.quat_wxyz,
                          translations=link.translations, **parameters)  # fmt: skip
    return resampler.sample(resampler.locate(times), "matrices")


def compose_topics(
    decoded: list, where: str, parent: str, child: str, mode: str = "screw", **parameters
):
    """``(times, quat_wxyz, translations, statement)``: :func:`compose` of the transforms of
    several topics, as any container decodes them: ``decoded`` holds ``(topic, parents,
    children, times, quat_wxyz, translations)`` for each topic; the transforms on
    :data:`TF_STATIC` are static. ``where`` starts the messages.

    Raises
    ------
    InputFileError
        If a transform is not finite, and as :func:`compose`.
    """
    parts = [
        TransformRecords(*rest, np.full(len(rest[2]), topic == TF_STATIC))
        for topic, *rest in decoded
    ]
    records = TransformRecords.joined(parts)
    if not (np.isfinite(records.quat_wxyz).all() and np.isfinite(records.translations).all()):
        raise InputFileError(f"{where}: a transform is not finite")
    return compose(records, parent, child, where, mode, **parameters)
