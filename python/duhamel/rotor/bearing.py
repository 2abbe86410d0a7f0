"""Bearings: linear stiffness and damping on a node's translations, constant or tabulated
against the spin speed, with an optional cubic law and rub."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from duhamel._engine.validate import as_float_array, finite_float, nonneg_float, positive_float
from duhamel.rotor._speed import constant_speed
from duhamel.rotor.dofs import local_dof_mapping, node_index

__all__ = ["Bearing", "Coefficient", "TableRangeWarning"]


class TableRangeWarning(UserWarning):
    """A speed-dependent bearing was evaluated outside its table of speeds (its end values
    are held there)."""


@functools.lru_cache(maxsize=256)
def _pchip(speeds: tuple[float, ...], values: tuple[float, ...]) -> Any:
    """The shape-preserving cubic (Fritsch-Carlson, scipy's PchipInterpolator) through the
    table; a single point is a constant."""
    from scipy.interpolate import PchipInterpolator

    if len(speeds) == 1:
        return lambda w: values[0]
    return PchipInterpolator(speeds, values, extrapolate=False)


def _contact(value: Any) -> tuple[float, float, float] | None:
    if value is None:
        return None
    try:
        parts = tuple(value)
    except TypeError:
        raise TypeError(
            "`contact` must be (clearance, stiffness) or (clearance, stiffness, friction), "
            f"got {type(value).__name__}"
        ) from None
    if len(parts) not in (2, 3):
        raise ValueError(
            "`contact` must be (clearance, stiffness) or (clearance, stiffness, friction), "
            f"got {len(parts)} values"
        )
    clearance = nonneg_float(parts[0], "contact clearance")
    stiffness = positive_float(parts[1], "contact stiffness")
    friction = nonneg_float(parts[2], "contact friction") if len(parts) == 3 else 0.0
    return clearance, stiffness, friction


#: The bearing's coefficients in the order of the 2 x 2 matrices ``[[xx, xy], [yx, yy]]``.
_COEFFICIENTS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")
#: Direct coefficients, which must be non-negative (at every table point).
_DIRECT = frozenset({"kxx", "kyy", "cxx", "cyy"})

#: A bearing coefficient: a number (constant), or one value per entry of ``Bearing.speeds``
#: (stored as a tuple of floats).
Coefficient = float | Sequence[float] | NDArray[np.float64]


def _speed_table(value: Any) -> tuple[float, ...] | None:
    if value is None:
        return None
    arr = as_float_array(value, "speeds", ndim=1)
    if arr.size == 0:
        raise ValueError("`speeds` must hold at least one spin speed (rad/s), got none")
    down = np.flatnonzero(np.diff(arr) <= 0.0)
    if down.size:
        i = int(down[0])
        raise ValueError(
            f"`speeds` must be strictly ascending, got speeds[{i + 1}] = {arr[i + 1]:g} after "
            f"speeds[{i}] = {arr[i]:g} rad/s"
        )
    return tuple(float(v) for v in arr)


def _is_table(value: Any) -> bool:
    if isinstance(value, str | bytes):
        return False
    try:
        return bool(np.ndim(value) > 0)
    except ValueError:  # a ragged nested sequence: let as_float_array report it
        return True


def _coefficient(
    value: Any, name: str, speeds: tuple[float, ...] | None
) -> float | tuple[float, ...]:
    """A coefficient as a float (constant) or a tuple of one float per speed of `speeds`."""
    if not _is_table(value):
        return nonneg_float(value, name) if name in _DIRECT else finite_float(value, name)
    if speeds is None:
        raise ValueError(
            f"`{name}` is a table of {np.size(value)} values, but the bearing has no `speeds`: "
            "give the spin speeds (rad/s) the values belong to as `speeds=`, or one number "
            "for a constant coefficient"
        )
    arr = as_float_array(value, name, ndim=1, finite=False)
    if arr.size != len(speeds):
        raise ValueError(
            f"`{name}` has {arr.size} values but `speeds` has {len(speeds)}: give one value "
            "per speed, or one number for a constant coefficient"
        )
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        i = int(bad[0])
        raise ValueError(
            f"`{name}` must be finite, got {float(arr[i])!r} at speeds[{i}] = {speeds[i]:g} rad/s"
        )
    if name in _DIRECT:
        neg = np.flatnonzero(arr < 0.0)
        if neg.size:
            i = int(neg[0])
            raise ValueError(
                f"`{name}` must be non-negative at every speed, got {float(arr[i])!r} at "
                f"speeds[{i}] = {speeds[i]:g} rad/s"
            )
    return tuple(float(v) for v in arr)


@dataclass(frozen=True)
class Bearing:
    """A bearing (or seal, or stator) acting on a node's translations ``(x, y)``.

    The linear force on the shaft is ``-[[kxx, kxy], [kyx, kyy]] (x, y) - [[cxx, cxy],
    [cyx, cyy]] (x', y')`` (N/m, N s/m): ``kxy`` is the force in x per unit y displacement,
    as the paper's ``k12``. Cross-coupled terms need not be symmetric (``kxy = -kyx`` is the
    destabilising cross-coupling of fluid films and seals).

    **Speed-dependent coefficients** (fluid-film bearings and seals, as ROSS's bearings with
    a ``frequency`` argument): give the spin speeds of a table as `speeds` (rad/s, strictly
    ascending) and any of ``kxx .. cyx`` as one value per speed (the others stay numbers:
    constant). At a spin speed the coefficients are interpolated between the table points
    (:meth:`stiffness_at`, :meth:`damping_at`) by the shape-preserving piecewise cubic
    (PCHIP, as ROSS 3; no overshoot, monotone data stay monotone) or, with
    ``interpolation="linear"``, linearly; both reproduce the table points exactly.
    **Outside the table the end values are held** with a :class:`TableRangeWarning` (no
    extrapolation: a fluid film's coefficients extrapolated soon turn negative). The table is
    against the *signed* spin speed, so a rotor spinning about ``-z`` (negative speed) reads
    the table at negative speeds (or holds its first value). :attr:`stiffness` and :attr:`damping`
    have no speed to evaluate such a bearing at and raise ``ValueError``; a
    :class:`~duhamel.rotor.Rotor` evaluates its bearings at the speed of each call.

    Optional nonlinear parts, added as :mod:`duhamel.elements`:

    * the paper's cubic law (its section 4.4), ``r_i = k_ii x_i beta (x_i / x_stat)^2`` on
      ``i = x, y``: a ``Cubic(dof, k3 = k_ii beta / x_stat^2)`` on each translation.
      ``x_stat`` (m) is a reference deflection; with ``x_stat=None`` the rotor uses the
      magnitude of the bearing's vertical static deflection under its own weight in the linear
      model (standard gravity 9.80665 m/s^2, weight along ``-y``), as the paper does. With
      speed-dependent ``kxx``, ``kyy``, ``k_ii`` is taken at the speed of the analysis.
    * ``contact = (clearance, stiffness[, friction])``: a radial rub
      (:class:`duhamel.elements.Contact`) of the node against a stator with that radial
      clearance (m), contact stiffness (N/m) and Coulomb friction coefficient.

    Parameters
    ----------
    node : int
        The rotor node.
    kxx, kyy : float or array_like
        Direct stiffnesses, ``>= 0`` (at every table point).
    kxy, kyx : float or array_like
        Cross-coupled stiffnesses.
    cxx, cyy : float or array_like
        Direct damping, ``>= 0`` (at every table point).
    cxy, cyx : float or array_like
        Cross-coupled damping.
    beta : float
        Cubic-law coefficient (0: linear).
    x_stat : float, optional
        Reference deflection of the cubic law, ``> 0``.
    contact : tuple, optional
        ``(clearance, stiffness)`` or ``(clearance, stiffness, friction)``.
    speeds : array_like, optional
        Keyword only. Spin speeds (rad/s, strictly ascending, finite) of the coefficient
        tables: each of ``kxx .. cyx`` is then a number (constant) or an array of
        ``len(speeds)`` values. Stored as a tuple, as are the tables.
    interpolation : {'pchip', 'linear'}
        Keyword only. How the tables are interpolated between their points.

    Raises
    ------
    ValueError
        Negative direct coefficients, non-finite values, a table without `speeds` or of
        another length, `speeds` not strictly ascending (messages name the parameter and,
        for a table, the offending speed).

    Examples
    --------
    >>> from duhamel.rotor import Bearing
    >>> b = Bearing(0, kxx=1e9, kyy=1e9, kxy=1e7, kyx=-1e7, beta=0.1, x_stat=2e-5)
    >>> b.stiffness.tolist()
    [[1000000000.0, 10000000.0], [-10000000.0, 1000000000.0]]
    >>> [e.k3 for e in b.elements(dof_x=0, dof_y=1, x_stat=b.x_stat)]
    [2.4999999999999997e+17, 2.4999999999999997e+17]

    A fluid-film bearing tabulated at 100, 200 and 400 rad/s (``cxy``, ``cyx`` constant):

    >>> fluid = Bearing(3, kxx=[1e7, 2e7, 4e7], kyy=[2e7, 3e7, 5e7],
    ...                 kxy=[1e6, 3e6, 8e6], kyx=[-1e6, -3e6, -8e6],
    ...                 cxx=[5e3, 4e3, 3e3], cyy=[6e3, 5e3, 4e3], speeds=[100, 200, 400])
    >>> fluid.is_speed_dependent
    True
    >>> fluid.stiffness_at(200.0).tolist()        # a table point
    [[20000000.0, 3000000.0], [-3000000.0, 30000000.0]]
    >>> round(float(fluid.stiffness_at(150.0)[0, 1]))  # PCHIP between 100 and 200 rad/s
    1954776
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     fluid.damping_at(1000.0).tolist()     # above the table: its last values, held
    [[3000.0, 0.0], [0.0, 4000.0]]
    >>> caught[0].category.__name__
    'TableRangeWarning'

    As every rotor component, it owns its matrices on its local dofs (:meth:`dof_mapping`),
    here at a spin speed:

    >>> list(fluid.dof_mapping()), fluid.K(200.0)[0].tolist(), fluid.M().any().item()
    (['x_0', 'y_0'], [20000000.0, 3000000.0], False)
    """

    node: int
    kxx: Coefficient
    kyy: Coefficient
    kxy: Coefficient = 0.0
    kyx: Coefficient = 0.0
    cxx: Coefficient = 0.0
    cyy: Coefficient = 0.0
    cxy: Coefficient = 0.0
    cyx: Coefficient = 0.0
    beta: float = 0.0
    x_stat: float | None = None
    contact: tuple[float, float, float] | None = None
    speeds: Sequence[float] | NDArray[np.float64] | None = field(default=None, kw_only=True)
    interpolation: str = field(default="pchip", kw_only=True)

    def __post_init__(self) -> None:
        if self.interpolation not in ("pchip", "linear"):
            raise ValueError(
                f"`interpolation` must be 'pchip' or 'linear', got {self.interpolation!r}"
            )
        object.__setattr__(self, "node", node_index(self.node))
        speeds = _speed_table(self.speeds)
        object.__setattr__(self, "speeds", speeds)
        for name in _COEFFICIENTS:
            object.__setattr__(self, name, _coefficient(getattr(self, name), name, speeds))
        object.__setattr__(self, "beta", finite_float(self.beta, "beta"))
        if self.x_stat is not None:
            object.__setattr__(self, "x_stat", positive_float(self.x_stat, "x_stat"))
        object.__setattr__(self, "contact", _contact(self.contact))

    @property
    def is_speed_dependent(self) -> bool:
        """Whether any coefficient is a table against :attr:`speeds`."""
        return any(isinstance(getattr(self, name), tuple) for name in _COEFFICIENTS)

    def _value(self, name: str, speed: float) -> float:
        value = getattr(self, name)
        if not isinstance(value, tuple):
            return float(value)
        table = self.speeds
        assert table is not None  # a tuple coefficient has its speeds (checked on creation)
        if not table[0] <= speed <= table[-1]:
            warnings.warn(
                f"the bearing at node {self.node} is evaluated at {speed:g} rad/s, outside its "
                f"table [{table[0]:g}, {table[-1]:g}] rad/s: its end values are held",
                TableRangeWarning,
                stacklevel=4,
            )
            return float(value[0] if speed < table[0] else value[-1])
        if speed in table:  # the table's own values, exactly
            return float(value[table.index(speed)])
        if self.interpolation == "linear":
            return float(np.interp(speed, table, value))
        return float(_pchip(table, value)(speed))

    def _matrix(self, names: tuple[str, str, str, str], speed: float) -> NDArray[np.float64]:
        xx, xy, yx, yy = (self._value(name, speed) for name in names)
        return np.array([[xx, xy], [yx, yy]])

    def _constant(self, what: str) -> None:
        if self.is_speed_dependent:
            raise ValueError(
                f"the bearing at node {self.node} has speed-dependent coefficients (tables "
                f"against `speeds`), so its {what} depends on the spin speed: use "
                f"{what}_at(speed)"
            )

    @property
    def stiffness(self) -> NDArray[np.float64]:
        """``[[kxx, kxy], [kyx, kyy]]`` of a constant-coefficient bearing.

        Raises ``ValueError`` for a speed-dependent bearing (use :meth:`stiffness_at`).
        """
        self._constant("stiffness")
        return self._matrix(("kxx", "kxy", "kyx", "kyy"), 0.0)

    @property
    def damping(self) -> NDArray[np.float64]:
        """``[[cxx, cxy], [cyx, cyy]]`` of a constant-coefficient bearing.

        Raises ``ValueError`` for a speed-dependent bearing (use :meth:`damping_at`).
        """
        self._constant("damping")
        return self._matrix(("cxx", "cxy", "cyx", "cyy"), 0.0)

    def stiffness_at(self, speed: float) -> NDArray[np.float64]:
        """``[[kxx, kxy], [kyx, kyy]]`` at spin speed `speed` (rad/s): the tables interpolated
        (PCHIP or linear, :attr:`interpolation`), their end values held outside them (with a
        :class:`TableRangeWarning`); constants as they are.

        Examples
        --------
        >>> from duhamel.rotor import Bearing
        >>> b = Bearing(0, kxx=[1e7, 3e7], kyy=2e7, speeds=[0.0, 1000.0])
        >>> b.stiffness_at(250.0).tolist()     # two points: PCHIP is the straight line
        [[15000000.0, 0.0], [0.0, 20000000.0]]
        """
        return self._matrix(("kxx", "kxy", "kyx", "kyy"), constant_speed(speed))

    def damping_at(self, speed: float) -> NDArray[np.float64]:
        """``[[cxx, cxy], [cyx, cyy]]`` at spin speed `speed` (rad/s), as :meth:`stiffness_at`.

        Examples
        --------
        >>> from duhamel.rotor import Bearing
        >>> b = Bearing(0, 1e7, 1e7, cxx=[800.0, 400.0], cyy=[800.0, 400.0], speeds=[0, 1000])
        >>> b.damping_at(500.0).tolist()
        [[600.0, 0.0], [0.0, 600.0]]
        """
        return self._matrix(("cxx", "cxy", "cyx", "cyy"), constant_speed(speed))

    @property
    def is_nonlinear(self) -> bool:
        """Whether the bearing has a cubic law or a rub contact."""
        return self.beta != 0.0 or self.contact is not None

    def elements(
        self,
        dof_x: int,
        dof_y: int,
        x_stat: float | None = None,
        *,
        speed: float | None = None,
    ) -> list[Any]:
        """The nonlinear parts as :mod:`duhamel.elements` on the global dofs `dof_x`, `dof_y`.

        Parameters
        ----------
        dof_x, dof_y : int
            Global indices of the node's x and y translations.
        x_stat : float, optional
            Reference deflection of the cubic law (default: the bearing's own `x_stat`);
            needed when ``beta != 0``.
        speed : float, optional
            Keyword only. Spin speed (rad/s) at which speed-dependent ``kxx``, ``kyy`` enter
            the cubic law; needed only then.

        Returns
        -------
        list
            ``Cubic`` elements on x and y (when ``beta != 0``) and a ``Contact`` (when
            `contact` is given).
        """
        from duhamel.elements import Contact, Cubic

        out: list[Any] = []
        if self.beta != 0.0:
            ref = self.x_stat if x_stat is None else positive_float(x_stat, "x_stat")
            if ref is None:
                raise ValueError(f"the cubic law of the bearing at node {self.node} needs `x_stat`")
            tabled = isinstance(self.kxx, tuple) or isinstance(self.kyy, tuple)
            if tabled and speed is None:
                raise ValueError(
                    f"the cubic law of the bearing at node {self.node} scales with kxx and kyy, "
                    "which depend on the spin speed: give `speed`"
                )
            w = 0.0 if speed is None else constant_speed(speed)
            for dof, name in ((dof_x, "kxx"), (dof_y, "kyy")):
                # k beta / x_stat^2, formed so that neither x_stat^2 nor the product overflows
                with np.errstate(all="ignore"):
                    k3 = (self._value(name, w) * self.beta / ref) / ref
                if not (np.isfinite(k3) and (k3 != 0.0 or self._value(name, w) == 0.0)):
                    raise ValueError(
                        f"the cubic law of the bearing at node {self.node}, {name} * `beta` / "
                        f"`x_stat`**2 = {self._value(name, w):g} * {self.beta:g} / {ref:g}**2, "
                        "is beyond the double range: check `x_stat` (the static deflection, "
                        "in m) and `beta`"
                    )
                out.append(Cubic(dof, k3=float(k3)))
        if self.contact is not None:
            clearance, stiffness, friction = self.contact
            out.append(
                Contact((dof_x, dof_y), clearance=clearance, stiffness=stiffness, friction=friction)
            )
        return out

    # ------------------------------------------------------------------ as a rotor component
    def dof_mapping(self) -> dict[str, int]:
        """Local dofs ``x_0, y_0``: the translations of :attr:`node` (local node 0)."""
        return local_dof_mapping(1, ("x", "y"))

    def M(self) -> NDArray[np.float64]:
        """Mass on :meth:`dof_mapping`: none, zeros."""
        return np.zeros((2, 2))

    def K(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Stiffness :meth:`stiffness_at` `speed` (rad/s) on :meth:`dof_mapping`."""
        return self.stiffness_at(speed)

    def C(self, speed: float = 0.0) -> NDArray[np.float64]:
        """Damping :meth:`damping_at` `speed` (rad/s) on :meth:`dof_mapping`."""
        return self.damping_at(speed)

    def G(self) -> NDArray[np.float64]:
        """Gyroscopic matrix on :meth:`dof_mapping`: none, zeros."""
        return np.zeros((2, 2))
