"""A suite of records or pairs with their scale factors and names (:class:`Suite`), as
the cases of :func:`duhamel.ensemble.solve_many` (one per record or pair and orientation)
and as coordinates of its :class:`~duhamel.ensemble.Ensemble`; exported from
:mod:`duhamel.records`."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array
from duhamel.loads import BaseAcceleration
from duhamel.records.motion import GroundMotion
from duhamel.records.pair import GroundMotionPair

__all__ = ["Suite"]


def _listed(value: Any, name: str) -> list[Any]:
    """`value` as a list, or a TypeError naming `name` when it is no sequence."""
    if (
        isinstance(value, str | bytes)
        or not isinstance(value, Sequence | np.ndarray)
        or np.ndim(value) == 0
    ):
        raise TypeError(f"`{name}` must be a sequence, got {type(value).__name__}")
    return list(value)


@dataclass(frozen=True, eq=False)
class Suite:
    """Records or pairs, one amplitude factor each, and their names.

    Parameters
    ----------
    records : sequence of GroundMotion or GroundMotionPair
        Unscaled.
    factors : array_like, optional
        One factor per record (default 1).
    names : sequence of str, optional
        Defaults to the records' names (made unique with ``#k`` where they repeat).

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.records import GroundMotion, GroundMotionPair, Suite
    >>> t = np.arange(0.0, 10.0, 0.01)
    >>> p = GroundMotionPair(GroundMotion(np.sin(t), 0.01, name="A_1"),
    ...                      GroundMotion(np.cos(t), 0.01, name="A_2"))
    >>> suite = Suite([p], factors=[2.0])
    >>> cases = suite.cases(orientations=(0.0, 90.0))
    >>> [(c["record"], c["factor"], c["orientation"]) for c in cases]
    [('A', 2.0, 0.0), ('A', 2.0, 90.0)]
    >>> x, y = suite.motions(cases[1])  # the pair scaled and turned by 90 degrees
    >>> bool(np.allclose(x.a, 2.0 * p.second.a))
    True
    """

    records: Sequence[GroundMotion | GroundMotionPair]
    factors: NDArray[np.float64] | None = None
    names: Sequence[str] | None = None

    def __post_init__(self) -> None:
        recs = _listed(self.records, "records")
        if not recs:
            raise ValueError("`records` is empty")
        for i, r in enumerate(recs):
            if not isinstance(r, GroundMotion | GroundMotionPair):
                raise TypeError(
                    f"`records[{i}]` must be a GroundMotion or GroundMotionPair, got "
                    f"{type(r).__name__}"
                )
        f = np.ones(len(recs)) if self.factors is None else self.factors
        f = as_float_array(f, "factors", ndim=1)
        if f.size != len(recs) or not np.all(np.isfinite(f)):
            raise ValueError(f"`factors` must be {len(recs)} finite numbers, got {f.size}")
        names = (
            [r.name for r in recs]
            if self.names is None
            else [str(n) for n in _listed(self.names, "names")]
        )
        if len(names) != len(recs):
            raise ValueError(f"`names` must be {len(recs)} strings, got {len(names)}")
        seen: dict[str, int] = {}
        unique = []
        for n in names:
            n = n or "record"
            seen[n] = seen.get(n, 0) + 1
            unique.append(n if seen[n] == 1 else f"{n}#{seen[n]}")
        object.__setattr__(self, "records", recs)
        object.__setattr__(self, "factors", f)
        object.__setattr__(self, "names", unique)

    def __len__(self) -> int:
        return len(self.records)

    def scaled(self) -> list[GroundMotion | GroundMotionPair]:
        """The records multiplied by their factors."""
        assert self.factors is not None
        return [r.scaled(float(f)) for r, f in zip(self.records, self.factors, strict=True)]

    def cases(self, orientations: ArrayLike = (0.0,)) -> list[dict[str, Any]]:
        """One dict per record and orientation, in that order: ``index`` (of the record),
        ``record`` (its name), ``factor`` and ``orientation`` (degrees: a pair is turned by
        it, so 0 and 90 apply each component along each axis of the building). All values
        are scalars: :meth:`duhamel.ensemble.Ensemble.to_xarray` makes them coordinates
        along ``case``. Pass them as `params` to :func:`duhamel.ensemble.solve_many` and
        build each case's loads with :meth:`loads` or :meth:`motions`."""
        angles = np.atleast_1d(as_float_array(orientations, "orientations"))
        if angles.ndim != 1:
            raise ValueError(f"`orientations` must be angles in degrees (1-D), got {angles.shape}")
        assert self.factors is not None and self.names is not None
        out = []
        for i, (r, f, n) in enumerate(zip(self.records, self.factors, self.names, strict=True)):
            own = angles if isinstance(r, GroundMotionPair) else angles[:1]
            for th in own:
                out.append({"index": i, "record": n, "factor": float(f), "orientation": float(th)})
        return out

    def motions(self, case: dict[str, Any]) -> tuple[GroundMotion, GroundMotion | None]:
        """The scaled (and for a pair, rotated) components of a case: ``(along x, along y)``;
        the second is None for a single record."""
        if not isinstance(case, Mapping) or not {"index", "factor"} <= set(case):
            raise TypeError(
                "`case` must be one of Suite.cases() (a dict with 'index', 'factor' and "
                f"'orientation'), got {type(case).__name__}"
            )
        i = case["index"]
        if isinstance(i, bool) or not isinstance(i, int | np.integer) or not 0 <= i < len(self):
            raise ValueError(f"`case`: 'index' must be a record of the suite, got {i!r}")
        r = self.records[i].scaled(float(case["factor"]))
        if isinstance(r, GroundMotionPair):
            r = r.rotated(float(case.get("orientation", 0.0)))
            return r.first, r.second
        return r, None

    def loads(
        self, case: dict[str, Any], x: ArrayLike, y: ArrayLike | None = None
    ) -> list[BaseAcceleration]:
        """The case's base accelerations: the first component on the dofs of the influence
        vector `x`, the second (of a pair) on `y`."""
        first, second = self.motions(case)
        out = [first.as_load(x)]
        if second is not None:
            if y is None:
                raise ValueError("a pair needs the influence vector `y` of its second component")
            out.append(second.as_load(y))
        return out
