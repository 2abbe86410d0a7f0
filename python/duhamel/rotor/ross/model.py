"""ROSS interoperability: a duhamel System from a ROSS ``Rotor`` (optional extra ``[ross]``).

`ROSS <https://github.com/petrobras/ross>`_ (PyPI ``ross-rotordynamics``) assembles rotor models
with 6 degrees of freedom per node, ``(x, y, z, alpha, beta, theta)``, and integrates them with
a Python-level Newmark loop or ``scipy.signal.lsim``. :func:`from_ross` takes ROSS's global
matrices ``M``, ``K``, ``C`` and ``G`` of ``M x'' + (C + speed G) x' + K x = f`` at one speed,
keeps the lateral dofs and returns a :class:`duhamel.System` for any duhamel integrator, with a
:class:`RossDofs` map between ROSS's dof numbering and the System's. See docs/ross.md.

ROSS is imported only by the caller (it is never imported here); any object with ROSS's
``M``, ``K``, ``C``, ``G`` methods and elements carrying ``dof_global_index`` works.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from duhamel._engine.validate import finite_float
from duhamel.rotor._speed import speed_or_law
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.ross.dofs import RossDofs, lateral_matrices
from duhamel.rotor.transient import add_couplings, nonzero, storage
from duhamel.speed import SpeedLaw
from duhamel.system import System

__all__ = ["RossDofs", "RossModel", "from_ross", "lateral_matrices"]


class _RossModelFields(NamedTuple):
    system: System
    dofs: RossDofs
    matrices: RotorMatrices


class RossModel(_RossModelFields):
    """What :func:`from_ross` returns: ``(system, dofs, matrices)``, and the analyses of a
    native :class:`~duhamel.rotor.Rotor` on the ROSS model (:attr:`rotor`).

    Attributes
    ----------
    system : System
        The duhamel System (background, couplings; no loads).
    dofs : RossDofs
        ROSS dof <-> System dof.
    matrices : RotorMatrices
        The lateral ROSS matrices ``(M, K, C, G)`` of ``M x'' + (C + speed G) x' + K x = f``
        in System order (``K`` and ``C`` at `frequency`; ``G`` per unit speed).
    """

    _source: Any = None  # the ROSS rotor (set by from_ross)
    _speed: Any = 0.0  # the speed (or law) and the coefficients' frequency of from_ross
    _frequency: float = 0.0
    _tables: tuple[Any, ...] = ()  # the speed-table elements from_ross added for a run-up

    def swap_bearing(self, journal: Any) -> Any:
        """Replace ROSS's bearing(s) at ``journal.node`` by the nonlinear
        :class:`~duhamel.rotor.ShortJournalBearing` `journal` in :attr:`system` (added to it,
        and returned): the element's force is the film force minus ROSS's linear bearing
        force at that node (its ``K`` and ``C`` at the model's frequency), which the System
        already carries, so that the model sees exactly the film force there while the
        background keeps ROSS's bearing as its linear part (good modes for the stepping).

        A rub or a cubic spring supplements a bearing instead: add
        ``duhamel.elements.Contact(dofs(n, "x"), dofs(n, "y"), ...)`` (or ``Cubic``) to
        :attr:`system` directly.

        Along a run-up a bearing whose coefficients depend on the frequency follows the
        speed as a table element (:mod:`duhamel.rotor.ross.runup`); swapped, that element is
        cancelled by its exact negative, and the journal's element subtracts ROSS's bearing
        at the initial speed, which the background carries: the model sees the film force
        alone there, alongside the other bearings that follow the speed.

        Raises
        ------
        ValueError
            Without a ROSS bearing at the node, or for a magnetic bearing there.

        Examples
        --------
        >>> import ross, duhamel                                   # doctest: +SKIP
        >>> from duhamel.rotor import ShortJournalBearing, from_ross
        >>> model = from_ross(ross.rotor_example(), 500.0)         # doctest: +SKIP
        >>> _ = model.swap_bearing(ShortJournalBearing(0, 0.05, 0.02, 1e-4, 0.02))  # doctest: +SKIP
        """
        from duhamel.rotor.journal import ShortJournalBearing

        if not isinstance(journal, ShortJournalBearing):
            raise TypeError(
                f"`journal` must be a ShortJournalBearing, got {type(journal).__name__}"
            )
        from duhamel.rotor.ross.magnetic import is_magnetic

        found = [
            b for b in getattr(self._source, "bearing_elements", ()) if int(b.n) == journal.node
        ]
        if any(is_magnetic(b) for b in found):
            raise ValueError(
                f"the ROSS bearing at node {journal.node} is a magnetic bearing (a closed loop "
                "with its controller): it is not swapped for a journal"
            )
        if not found:
            raise ValueError(f"the ROSS model has no bearing at node {journal.node} to replace")
        k0, c0 = np.zeros((2, 2)), np.zeros((2, 2))
        dx, dy = self.dofs(journal.node, "x"), self.dofs(journal.node, "y")
        for b in found:
            varies = np.ndim(getattr(b, "frequency", None)) == 1 and len(b.frequency) > 1
            if varies and isinstance(self._speed, SpeedLaw):
                # along a run-up the bearing follows the speed as a table element: cancel it
                from duhamel.rotor.ross.runup import cancelling

                self.system.add(cancelling(self._tables, dx, dy))
            for m, kind in ((k0, "k"), (c0, "c")):
                for (i, j), a in zip(
                    ((0, 0), (0, 1), (1, 0), (1, 1)), ("xx", "xy", "yx", "yy"), strict=True
                ):
                    m[i, j] += float(getattr(b, f"{kind}{a}_interpolated")(self._frequency))
        element = journal.element(dx, dy, self._speed, k0=k0, c0=c0)
        self.system.add(element)
        return element

    @property
    def rotor(self) -> Any:
        """The ROSS model as a :class:`~duhamel.rotor.ross.analyses.RossRotor`: what a native
        :class:`~duhamel.rotor.Rotor` offers at constant speed (``modes``, ``campbell``,
        ``critical_speeds``, ``frequency_response``, ``unbalance_response``,
        ``level1_stability``, ``critical_speed_map``...), with ROSS's ``K`` and ``C``
        re-evaluated at each speed (``frequency = speed``, as ROSS's own analyses)."""
        from duhamel.rotor.ross.analyses import RossRotor

        return RossRotor(self._source, self.dofs, self.matrices)

    def modes(self, speed: float = 0.0, n: int | None = None) -> Any:
        """:meth:`Rotor.modes <duhamel.rotor.Rotor.modes>` of the ROSS model (:attr:`rotor`)."""
        return self.rotor.modes(speed, n)

    def natural_frequencies(self, speed: float = 0.0, n: int | None = None) -> Any:
        """:meth:`Rotor.natural_frequencies <duhamel.rotor.Rotor.natural_frequencies>`."""
        return self.rotor.natural_frequencies(speed, n)

    def campbell(self, speeds: Any, n_modes: int | None = None, *, track: bool = True) -> Any:
        """:meth:`Rotor.campbell <duhamel.rotor.Rotor.campbell>` of the ROSS model."""
        return self.rotor.campbell(speeds, n_modes, track=track)

    def plot_campbell(self, speeds: Any, n_modes: int | None = None, **kwargs: Any) -> Any:
        """:meth:`Rotor.plot_campbell <duhamel.rotor.Rotor.plot_campbell>`."""
        return self.rotor.plot_campbell(speeds, n_modes, **kwargs)

    def critical_speeds(self, speeds: Any, **kwargs: Any) -> Any:
        """:meth:`Rotor.critical_speeds <duhamel.rotor.Rotor.critical_speeds>`."""
        return self.rotor.critical_speeds(speeds, **kwargs)

    def frequency_response(self, speed: Any, frequencies: Any, inputs: Any, outputs: Any) -> Any:
        """:meth:`Rotor.frequency_response <duhamel.rotor.Rotor.frequency_response>`, dofs
        as :class:`RossDofs` labels (``"x_2"``, ``"beta_3"``), indices or ``(node, dir)``."""
        return self.rotor.frequency_response(speed, frequencies, inputs, outputs)

    def frequency_response_map(
        self, speeds: Any, frequencies: Any, inputs: Any, outputs: Any
    ) -> Any:
        """:meth:`Rotor.frequency_response_map <duhamel.rotor.Rotor.frequency_response_map>`."""
        return self.rotor.frequency_response_map(speeds, frequencies, inputs, outputs)

    def acceleration_stiffness(self) -> Any:
        """ROSS's angular-acceleration stiffness ``Ksdt`` (lateral block, System order): a
        run-up at the rate ``alpha = d omega / dt`` adds ``alpha Ksdt`` to the stiffness, as
        ROSS's ``run_time_response`` with a speed array does. from_ross does not add it (a
        speed law's rate jumps to zero at its end); for a run over a linear ramp add it as
        ``system.add(duhamel.elements.LinearCoupling(K=alpha * model.acceleration_stiffness()))``.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import from_ross
        >>> class Disk:
        ...     dof_global_index = {"x_0": 0, "y_0": 1, "alpha_0": 2, "beta_0": 3}
        >>> class Toy:
        ...     elements = [Disk()]
        ...     def M(self, f=None): return np.diag([2.0, 2.0, 0.1, 0.1])
        ...     def K(self, f): return np.diag([8e4, 8e4, 1e4, 1e4])
        ...     def C(self, f): return np.zeros((4, 4))
        ...     def G(self): return np.zeros((4, 4))
        ...     def Ksdt(self): return np.array([[0, 0, 0, 0], [0, 0, 0, 0],
        ...                                      [0, 0, 0, -0.2], [0, 0, 0, 0]])
        >>> from_ross(Toy(), 0.0).acceleration_stiffness()[2, 3]
        np.float64(-0.2)
        """
        if self._source is None or not hasattr(self._source, "Ksdt"):
            raise ValueError("the ROSS model has no `Ksdt` (angular-acceleration stiffness)")
        K = np.asarray(self._source.Ksdt(), dtype=float)
        keep = self.dofs.ross_index
        dropped = np.setdiff1d(np.arange(self.dofs.n_ross), keep)
        if K.shape != (self.dofs.n_ross, self.dofs.n_ross):
            raise ValueError(f"ROSS's `Ksdt` has shape {K.shape}")
        cross = max(np.abs(K[np.ix_(keep, dropped)]).max(initial=0.0),
                    np.abs(K[np.ix_(dropped, keep)]).max(initial=0.0))  # fmt: skip
        if cross > 1e-12 * max(float(np.abs(K).max()), 1e-300):
            raise ValueError("ROSS's `Ksdt` couples the lateral dofs to the dropped ones")
        return K[np.ix_(keep, keep)]

    def unbalance_response(self, speeds: Any, unbalances: Any) -> Any:
        """Steady-state unbalance response (:func:`duhamel.rotor.unbalance_response`) with
        these matrices (ROSS's ``K`` and ``C`` at the model's `frequency`; for
        frequency-dependent bearings use ``model.rotor.unbalance_response``, which
        re-evaluates them at each speed), unbalances at ROSS nodes."""
        from duhamel.rotor.unbalance import unbalance_response

        magnetic = self.rotor.magnetic
        if magnetic:  # their dynamic stiffness at each speed (:mod:`duhamel.rotor._amb_linear`)
            from duhamel.rotor._amb_linear import amb_axes, with_bearings_at

            at = with_bearings_at(lambda w: self.matrices, amb_axes(magnetic, self.dofs))
            return unbalance_response(at, speeds, unbalances, dof=self.dofs)
        return unbalance_response(self.matrices, speeds, unbalances, dof=self.dofs)


def from_ross(
    rotor: Any,
    speed: Any,
    *,
    frequency: float | None = None,
    sparse: bool = False,
    dofs: str = "lateral",
) -> RossModel:
    """A duhamel :class:`~duhamel.System` from a ROSS ``Rotor`` at constant `speed`.

    ROSS's global matrices ``M(frequency)``, ``K(frequency)``, ``C(frequency)`` (ROSS >= 3:
    with ``speed=speed``) and ``G()`` describe ``M x'' + (C + speed G) x' + K x = f`` on 6 dofs
    per node, ``(x, y, z, alpha, beta, theta)``. The lateral dofs ``(x, y, alpha, beta)`` are
    kept, in ROSS's order; they are duhamel's ``(x, y, theta_x, theta_y)`` **without any sign
    change** (ROSS's ``alpha`` is the rotation about +x, ``-dy/dz`` in bending, and ``beta``
    about +y, ``dx/dz``; its ``G`` has duhamel's sign: both give the same matrices for the same
    rotor to round-off). The axial ``z`` and torsional ``theta`` dofs are dropped, exactly as
    ROSS's ``convert_6dof_to_4dof``; ROSS's constant-speed matrices do not couple them to the
    lateral ones (checked: a coupling above 1e-12 of a matrix's largest entry raises). A model
    that already has 4 dofs per node, or one converted with ``convert_6dof_to_4dof``, is taken
    as it is.

    The System is built as :meth:`duhamel.rotor.Rotor.system` builds it:

    * background (exact in :class:`duhamel.Semianalytic`): ``M`` and ``K_sym = (K + K^T)/2``,
      with ``C = (C_ross + C_ross^T)/2`` as its damping matrix when that is nonzero (its
      modal diagonal is exact, the rest a pseudo-force);
    * ``LinearCoupling(C=speed * G)``: the gyroscopic terms (omitted at zero speed);
    * ``LinearCoupling(K=(K - K^T)/2, C=(C - C^T)/2)``: cross-coupled bearing and seal
      coefficients (omitted when zero).

    All damping is ROSS's ``C`` (bearings, seals, shaft ``alpha``/``beta`` damping); ROSS's
    example rotor has none, and neither does the System then.

    Parameters
    ----------
    rotor : ross.Rotor
        The ROSS model.
    speed : float or speed law
        Spin speed (rad/s), or a :mod:`duhamel.speed` law (``LinearRunUp``): then the
        background takes ROSS's matrices at the initial speed, the gyroscopic coupling is
        scaled by ``omega(t)``, and every frequency-dependent bearing and seal follows the
        speed (ROSS's coefficient curves sampled over the range of the law, PCHIP between
        the samples: :mod:`duhamel.rotor.ross.runup`). ROSS's angular-acceleration
        stiffness ``Ksdt`` of a run-up is not added (:meth:`RossModel.acceleration_stiffness`
        gives it).
    frequency : float, optional
        Keyword only. Excitation frequency at which frequency-dependent bearing and seal
        coefficients are evaluated; default `speed`, as ROSS's ``run_time_response``.
    sparse : bool
        Keyword only. Store the matrices as ``scipy.sparse`` CSR (large models).
    dofs : {"lateral", "all"}
        Keyword only. ``"all"``: keep ROSS's axial ``z`` and torsional ``theta`` dofs too (all
        6 per shaft node, in ROSS's order): axial and torsional modes (labelled
        ``"axial"``, ``"torsional"`` in :attr:`Modes.whirl`), torque and axial loads
        (``model.dofs(node, "theta")``), drive-train transients. ROSS's constant-speed
        matrices do not couple them to the lateral ones.

    Returns
    -------
    RossModel
        ``(system, dofs, matrices)``: the System (no loads: add them with
        ``system.add_load``, e.g. ``dofs.unbalance(...)`` or ``dofs.loads(F, t)``), the
        :class:`RossDofs` map, and the lateral ``(M, K, C, G)``.

    Raises
    ------
    ValueError
        If ``M`` is not symmetric, the lateral dofs are coupled to the dropped ones, or the
        dof names are not ROSS's. The System itself refuses a ``K_sym`` that is not positive
        semidefinite (a seal with a large negative direct stiffness) when it is solved.

    Examples
    --------
    ROSS's example rotor (6 shaft elements, 2 disks, 2 bearings; 7 nodes, 28 lateral dofs) at
    500 rad/s, with an unbalance and a rub at the disk of node 2:

    >>> import duhamel, ross                                            # doctest: +SKIP
    >>> from duhamel.rotor import from_ross
    >>> system, dofs, _ = from_ross(ross.rotor_example(), speed=500.0)  # doctest: +SKIP
    >>> system                                                          # doctest: +SKIP
    System(n_dof=28, damping='none', loads=0, couplings=1)
    >>> dofs(2, "x"), dofs(2, "y"), dofs.labels[8:12]                   # doctest: +SKIP
    (8, 9, ('x_2', 'y_2', 'alpha_2', 'beta_2'))
    >>> _ = system.add_load(dofs.unbalance(2, m_e=1e-3, speed=500.0))   # doctest: +SKIP
    >>> rub = duhamel.elements.Contact(dofs(2, "x"), dofs(2, "y"),    # doctest: +SKIP
    ...                                clearance=8e-5, stiffness=5e7, friction=0.1)
    >>> _ = system.add(rub)                                             # doctest: +SKIP
    >>> sol = duhamel.solve(system, duhamel.Semianalytic(), t_end=0.5, dt=1e-4)  # doctest: +SKIP
    >>> dofs.to_ross(sol.x).shape     # as ROSS's run_time_response(...).yout  # doctest: +SKIP
    (5001, 42)

    Without ROSS, anything with its interface does (here one rigid disk on two springs):

    >>> import numpy as np
    >>> class Disk:
    ...     dof_global_index = {"x_0": 0, "y_0": 1, "z_0": 2}
    >>> class Toy:                                      # a ROSS Rotor's interface
    ...     elements = [Disk()]
    ...     def M(self, f=None): return np.eye(3)
    ...     def K(self, f): return np.diag([1e4, 2e4, 5e3])
    ...     def C(self, f): return np.zeros((3, 3))
    ...     def G(self): return np.zeros((3, 3))
    >>> toy = Toy()
    >>> model = from_ross(toy, speed=0.0)
    >>> model.system.n_dof, model.dofs.labels, model.dofs(0, "y")
    (2, ('x_0', 'y_0'), 1)
    """
    w = speed_or_law(speed)  # a float, or a varying law (a run-up)
    law = w if isinstance(w, SpeedLaw) else None
    w0 = float(np.asarray(law.omega(np.array([0.0])))[0]) if law is not None else float(w)
    if law is not None and frequency is not None:
        raise ValueError(
            "`frequency` is for a constant speed: along a run-up the bearing and seal "
            "coefficients follow the speed"
        )
    freq = w0 if frequency is None else finite_float(frequency, "frequency")
    if dofs not in ("lateral", "all"):
        raise ValueError(f"`dofs` must be 'lateral' or 'all', got {dofs!r}")
    matrices, dofs = lateral_matrices(rotor, w0, freq, every=dofs == "all")
    M, K, C, G = matrices
    names = dofs.labels

    conv = storage(sparse)
    k_sym, k_skew = (K + K.T) / 2.0, (K - K.T) / 2.0
    c_sym, c_skew = (C + C.T) / 2.0, (C - C.T) / 2.0
    if nonzero(c_sym):
        system = System(conv(M), conv(k_sym), conv(c_sym))
    else:
        system = System(conv(M), conv(k_sym))
    from duhamel.rotor.ross.magnetic import is_magnetic, magnetic_bearing

    magnetic = [
        magnetic_bearing(b) for b in getattr(rotor, "bearing_elements", ()) if is_magnetic(b)
    ]
    add_couplings(system, G, w, k_skew, c_skew, conv, magnetic, dofs)
    tables: tuple[Any, ...] = ()
    if law is not None:
        from duhamel.rotor.ross.runup import ross_speed_tables

        tables = tuple(ross_speed_tables(rotor, dofs, law, w0))
        for element in tables:
            system.add(element)
    if len(set(names)) == len(names):
        system.label_dofs(names)
    model = RossModel(system=system, dofs=dofs, matrices=matrices)
    model._source = rotor
    model._speed, model._frequency = w, freq
    model._tables = tables
    return model
