"""Complex (damped) modes of a rotor at one speed: eigenpairs, MAC and whirl sense.

Degrees of freedom as in :mod:`duhamel.rotor.dofs` (4 per node, ``(x, y, theta_x,
theta_y)``). Forward whirl is an orbit in the sense of the spin, from +x towards +y.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

__all__ = ["Modes", "complex_modes", "modes_of", "split_eigenvalues"]

#: Eigenvalues with ``Im(lambda) <= ZERO_FREQUENCY_RTOL * max|lambda|`` are not oscillatory:
#: rigid-body modes (whose defective zero eigenvalues come out of the eigensolver as pairs of
#: size about ``sqrt(eps) max|lambda|``).
ZERO_FREQUENCY_RTOL = 1e-6
#: A mode ``e^{lambda t}`` is overdamped (not oscillatory) when it decays by more than the
#: double precision, ``e^{-OVERDAMPED_DECAY} = eps``, before its first zero crossing (a quarter
#: of its period): ``|Re(lambda)| pi / (2 Im(lambda)) >= ln(1 / eps)``, i.e. damping ratio
#: above 0.99905. Real eigenvalue pairs split by round-off into ``sigma +- i eps'`` (a
#: relative ``Im`` of ``sqrt(eps)`` at most, near a double root) and the nearly real pairs
#: that gyroscopic coupling makes of two overdamped motions are far beyond it; every mode
#: whose oscillation could show in a computed response is far below it.
OVERDAMPED_DECAY = float(np.log(1.0 / np.finfo(float).eps))
#: Orbit sense: a node counts when its amplitude is at least this fraction of the largest
#: node's, and its signed orbit area at least ``PLANAR_RTOL`` times its amplitude.
NODE_RTOL = 1e-4
PLANAR_RTOL = 1e-6
#: Eigenvalues within this relative distance form a cluster (a degenerate pair).
CLUSTER_RTOL = 1e-8


@dataclass(frozen=True, eq=False)
class Modes:
    """Complex (damped) modes of the rotor at one speed, ascending in frequency.

    Each mode is a solution ``x(t) = Re(shape e^{lambda t})`` of the free rotor with
    ``Im(lambda) > 0``.

    Attributes
    ----------
    speed : float
        Spin speed (rad/s).
    eigenvalues : ndarray of complex, shape (n_modes,)
        ``lambda = -zeta omega_n + i omega_d``.
    shapes : ndarray of complex, shape (n_dof, n_modes)
        Mode shapes, scaled so that the translation of largest magnitude is 1 (real).
    whirl : tuple of str
        ``"forward"`` (every moving node orbits in the sense of the spin: from +x towards +y
        for ``speed >= 0``), ``"backward"``, ``"mixed"`` (nodes disagree) or ``"planar"``
        (straight-line orbits); ``"torsional"`` or ``"axial"`` for the modes of a model
        with those dofs (``from_ross(..., dofs="all")``) that hardly move laterally.
        Within a pair of equal eigenvalues (an axisymmetric rotor, or any rotor at zero
        speed with isotropic bearings) the shapes are chosen as the backward and the
        forward circular orbits.
    length_scale : float
        Length (m) that weights the rotations against the translations in :meth:`mac` and in
        the whirl (the rotor's mean element length; 1 by default).
    overdamped : ndarray of complex
        The finite eigenvalues that are not oscillatory, sorted by decay rate (slowest
        first): overdamped motions (damping ratio above 0.99905, see
        :data:`OVERDAMPED_DECAY`; real pairs, and nearly real pairs that the gyroscopic terms
        couple) and rigid-body modes (eigenvalue 0). Never listed as natural frequencies.
    """

    speed: float
    eigenvalues: NDArray[np.complex128]
    shapes: NDArray[np.complex128]
    whirl: tuple[str, ...]
    length_scale: float = 1.0
    overdamped: NDArray[np.complex128] = field(default_factory=lambda: np.zeros(0, dtype=complex))
    #: Per node the dofs ``(x, y, theta_x, theta_y)`` and optionally ``(z, theta)`` (-1
    #: where a node has none: a point mass's tilts); None: 4 per node in order.
    layout: NDArray[np.intp] | None = None

    @property
    def n_modes(self) -> int:
        """Number of modes."""
        return int(self.eigenvalues.size)

    @property
    def frequencies(self) -> NDArray[np.float64]:
        """Damped natural frequencies ``Im(lambda)`` (rad/s)."""
        return self.eigenvalues.imag.copy()

    @property
    def damping_ratios(self) -> NDArray[np.float64]:
        """``-Re(lambda) / |lambda|`` (negative: unstable)."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    @property
    def log_dec(self) -> NDArray[np.float64]:
        """Logarithmic decrement ``-2 pi Re(lambda) / Im(lambda)`` (negative: unstable)."""
        return -2.0 * np.pi * self.eigenvalues.real / self.eigenvalues.imag

    def summary(self) -> str:
        """A table of the modes: frequency (rad/s and Hz), damping ratio, log decrement and
        whirl, then the overdamped eigenvalues.

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor.modes import complex_modes
        >>> M, K = np.eye(4), np.diag([4.0, 4.0, 100.0, 100.0])
        >>> print(complex_modes(M, 0.1 * np.eye(4), K, speed=0.0, n=2).summary())
        mode  freq [rad/s]   freq [Hz]     zeta   log dec  whirl
           0        1.9994      0.3182   0.0250    0.1571  backward
           1        1.9994      0.3182   0.0250    0.1571  forward
        overdamped: none
        """
        lines = [f"{'mode':>4}  {'freq [rad/s]':>12}  {'freq [Hz]':>10}  {'zeta':>7}  "
                 f"{'log dec':>8}  whirl"]  # fmt: skip
        for j in range(self.n_modes):
            f = float(self.eigenvalues[j].imag)
            lines.append(
                f"{j:>4}  {f:>12.4f}  {f / (2 * np.pi):>10.4f}  "
                f"{self.damping_ratios[j]:>7.4f}  {self.log_dec[j]:>8.4f}  {self.whirl[j]}"
            )
        over = ", ".join(f"{v:.4g}" for v in self.overdamped) if self.overdamped.size else "none"
        lines.append(f"overdamped: {over}")
        return "\n".join(lines)

    def mac(self, other: Modes) -> NDArray[np.float64]:
        """Modal assurance criterion between these mode shapes and `other`'s.

        ``MAC[i, j] = |u_i^H v_j|^2 / (|u_i|^2 |v_j|^2)`` on the complex displacement shapes
        (``u_i = shapes[:, i]``, ``v_j = other.shapes[:, j]``), with the rotations multiplied
        by :attr:`length_scale` so that every entry is a length. 1 for proportional shapes, 0
        for orthogonal ones (a forward and a backward circular orbit of an isotropic rotor).

        Parameters
        ----------
        other : Modes
            Modes of a model with the same degrees of freedom (e.g. at another speed).

        Returns
        -------
        ndarray, shape (n_modes, other.n_modes)

        Examples
        --------
        >>> import numpy as np
        >>> from duhamel.rotor import STEEL, Bearing, Disk, Rotor, Shaft
        >>> rotor = Rotor([Shaft(0.25, 0.05, material=STEEL)] * 4, [Disk(2, 30.0, 0.3, 0.16)],
        ...               [Bearing(0, 1e7, 1e7), Bearing(4, 1e7, 1e7)])
        >>> a, b = rotor.modes(100.0, n=2), rotor.modes(150.0, n=2)
        >>> a.whirl, np.round(a.mac(b), 6).tolist()
        (('backward', 'forward'), [[1.0, 0.0], [0.0, 1.0]])
        """
        if not isinstance(other, Modes):
            raise TypeError(f"`other` must be Modes, got {type(other).__name__}")
        if other.shapes.shape[0] != self.shapes.shape[0]:
            raise ValueError(
                f"`other` has {other.shapes.shape[0]} degrees of freedom, these modes "
                f"{self.shapes.shape[0]}"
            )
        return _mac(self.shapes, other.shapes, self.length_scale, self.layout)

    def mac_with(self, shape: NDArray[np.complex128]) -> NDArray[np.float64]:
        """:meth:`mac` of each mode with one `shape` (a column over the same dofs)."""
        one = np.asarray(shape, dtype=complex).reshape(-1, 1)
        return _mac(self.shapes, one, self.length_scale, self.layout)[:, 0]


def complex_modes(
    M: NDArray[np.float64],
    D: NDArray[np.float64],
    K: NDArray[np.float64],
    *,
    speed: float,
    n: int | None = None,
    length_scale: float = 1.0,
    layout: NDArray[np.intp] | None = None,
) -> Modes:
    """The oscillatory modes of ``lambda^2 M + lambda D + K`` (``D = C + speed G``), the
    lowest `n` (all by default), with circular pairs and their whirl sense.

    Parameters
    ----------
    M, D, K : ndarray, shape (n_dof, n_dof)
        Mass, damping plus gyroscopic, stiffness; ``n_dof`` a multiple of 4 (node-wise
        ``(x, y, theta_x, theta_y)``).
    speed : float
        Keyword only. Spin speed (rad/s): negative speeds flip the whirl labels.
    n : int, optional
        Keyword only. Keep the lowest `n` modes.
    length_scale : float
        Keyword only. Weight of the rotations in the MAC and whirl (m).
    layout : ndarray of int, shape (n_nodes, 4), optional
        Keyword only. Per node its dofs ``(x, y, theta_x, theta_y)``, -1 for none (a point
        mass's tilts); default 4 per node in order.

    Returns
    -------
    Modes

    Examples
    --------
    A point mass on isotropic springs (rotations held by unit stiffness and inertia):

    >>> import numpy as np
    >>> from duhamel.rotor.modes import complex_modes
    >>> M, K = np.diag([1.0, 1.0, 1.0, 1.0]), np.diag([4.0, 4.0, 100.0, 100.0])
    >>> modes = complex_modes(M, np.zeros((4, 4)), K, speed=0.0, n=2)
    >>> modes.frequencies.tolist(), modes.whirl
    ([2.0, 2.0], ('backward', 'forward'))
    """
    from duhamel.rotor._sparse_modes import lowest_modes, sparse_worth

    found = None
    if sparse_worth(M.shape[0], n):  # a few modes of a large model: shift-invert
        near = lowest_modes(M, D, K, int(n), oscillatory)  # type: ignore[arg-type]
        if near is not None:
            lam, vec, scale = near
            found = split_eigenvalues(lam, vec, scale)
    if found is None:
        found = _complex_modes(M, D, K)
    return modes_of(*found, speed=speed, n=n, length_scale=length_scale, layout=layout)


def modes_of(
    lam: NDArray[np.complex128],
    shapes: NDArray[np.complex128],
    over: NDArray[np.complex128],
    *,
    speed: float,
    n: int | None = None,
    length_scale: float = 1.0,
    layout: NDArray[np.intp] | None = None,
) -> Modes:
    """:class:`Modes` of oscillatory eigenpairs (ascending, as :func:`_complex_modes` gives
    them) and the other finite eigenvalues `over`: the lowest `n`, shapes normalised on the
    translations of `layout`, circular pairs, whirl senses."""
    if n is not None:
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
            raise ValueError(f"`n` must be a positive integer, got {n!r}")
        lam, shapes = lam[:n], shapes[:, :n]
    ell = length_scale
    every = _nodes(layout, shapes.shape[0])
    nodes = every[:, :4]
    if layout is not None:  # normalised on this layout's translations
        shapes = _normalise(shapes, nodes)
    shapes = _circular_pairs(lam, shapes, ell, nodes)
    whirl = tuple(_kind(shapes[:, j], every, ell) for j in range(lam.size))
    if speed < 0.0:  # spinning about -z: the whirl sense relative to the spin flips
        flip = {"forward": "backward", "backward": "forward"}
        whirl = tuple(flip.get(k, k) for k in whirl)
    return Modes(speed, lam, shapes, whirl, length_scale=ell, overdamped=over, layout=layout)


def _complex_modes(
    M: NDArray[np.float64], D: NDArray[np.float64], K: NDArray[np.float64]
) -> tuple[NDArray[np.complex128], NDArray[np.complex128], NDArray[np.complex128]]:
    """Oscillatory eigenpairs of ``lambda^2 M + lambda D + K``, ``Im(lambda) > 0``, ascending,
    and the other finite eigenvalues (overdamped and rigid-body, slowest first).

    Without damping and gyroscopic terms (``D = 0``, ``K`` symmetric, ``M`` positive
    definite) the eigenvalues are ``+-i omega`` with ``omega^2`` those of ``(K, M)``: solved by
    the symmetric eigensolver, exactly as the state-space problem but faster and to full
    accuracy. Otherwise the QZ algorithm on the scaled first-order pencil.
    """
    import scipy.linalg

    n = M.shape[0]
    if not np.any(D) and np.array_equal(K, K.T):
        try:
            lam2, vec = scipy.linalg.eigh(K, M, check_finite=False)
        except np.linalg.LinAlgError:  # singular M (massless dofs): the general path
            pass
        else:
            omega = np.sqrt(np.clip(lam2, 0.0, None))
            keep = omega > ZERO_FREQUENCY_RTOL * float(omega.max())
            rigid = np.zeros(2 * int(np.count_nonzero(~keep)), dtype=complex)
            return 1j * omega[keep], _normalise(vec[:, keep].astype(complex)), rigid
    kmax, mmax = float(np.max(np.abs(np.diag(K)))), float(np.max(np.diag(M)))
    s = np.sqrt(kmax / mmax) if kmax > 0.0 and mmax > 0.0 else 1.0
    eye, zero = np.eye(n), np.zeros((n, n))
    A = np.block([[zero, s * eye], [-K / s, -D]])
    B = np.block([[eye, zero], [zero, M]])
    lam, vec = scipy.linalg.eig(A, B, check_finite=False)
    return split_eigenvalues(lam, vec[:n] / s)


def split_eigenvalues(
    lam: NDArray[np.complex128], vec: NDArray[np.complex128], scale: float | None = None
) -> tuple[NDArray[np.complex128], NDArray[np.complex128], NDArray[np.complex128]]:
    """The finite eigenvalues `lam` (shapes `vec`, the dofs' rows) as the oscillatory
    eigenpairs with ``Im(lambda) > 0``, ascending and normalised, and the other finite
    eigenvalues (overdamped and rigid-body, slowest first); `scale` the largest ``|lambda|``
    of the problem (default: of `lam`), the rigid-body test's reference."""
    n = vec.shape[0]
    finite = np.isfinite(lam)
    lam, vec = lam[finite], vec[:, finite]
    if lam.size == 0:
        empty = np.zeros(0, dtype=complex)
        return empty, np.zeros((n, 0), dtype=complex), empty
    top = float(np.max(np.abs(lam))) if scale is None else float(scale)
    keep = oscillatory(lam, top)
    other = ~keep & ~oscillatory(lam.conj(), top)
    over = lam[other]
    over = over[np.lexsort((over.imag, -over.real))]
    lam, vec = lam[keep], vec[:, keep]
    order = np.argsort(lam.imag, kind="stable")
    return lam[order], _normalise(vec[:, order]), over


def oscillatory(lam: NDArray[np.complex128], scale: float) -> NDArray[np.bool_]:
    """Which eigenvalues are oscillatory modes with ``Im(lambda) > 0``: not rigid-body
    (``Im(lambda) > ZERO_FREQUENCY_RTOL scale``, `scale` the largest ``|lambda|``) and not
    overdamped (see :data:`OVERDAMPED_DECAY`)."""
    im = lam.imag
    return (im > ZERO_FREQUENCY_RTOL * scale) & (
        np.abs(lam.real) * (np.pi / 2.0) < OVERDAMPED_DECAY * im
    )


def _kind(shape: NDArray[np.complex128], every: NDArray[np.intp], ell: float) -> str:
    """The whirl of a lateral mode (:func:`_whirl`); ``"axial"`` or ``"torsional"`` for a
    mode of a layout with axial and torsional dofs (columns ``z``, ``theta``) whose lateral
    motion is below a millionth of the whole."""
    g = _gather(shape, every)
    if every.shape[1] > 4:
        lateral = float(np.sum(np.abs(g[:, :2]) ** 2) + ell**2 * np.sum(np.abs(g[:, 2:4]) ** 2))
        axial = float(np.sum(np.abs(g[:, 4]) ** 2))
        torsion = float(ell**2 * np.sum(np.abs(g[:, 5]) ** 2)) if every.shape[1] > 5 else 0.0
        if lateral <= 1e-6 * (lateral + axial + torsion):
            return "torsional" if torsion >= axial else "axial"
    return _whirl(g[:, :4], ell)


def _nodes(layout: NDArray[np.intp] | None, n_dof: int) -> NDArray[np.intp]:
    """`layout`, or 4 dofs per node in order."""
    if layout is None:
        return np.arange(n_dof - n_dof % 4, dtype=np.intp).reshape(-1, 4)
    return np.asarray(layout, dtype=np.intp)


def _gather(v: NDArray[np.complex128], nodes: NDArray[np.intp]) -> NDArray[np.complex128]:
    """The values of `v` (dofs on axis 0) per node and direction, zero where absent:
    shape ``(n_nodes, 4, ...)``."""
    out = np.where((nodes >= 0).reshape(nodes.shape + (1,) * (v.ndim - 1)), v[nodes], 0.0)
    return np.asarray(out, dtype=complex)


def _weighted(
    shapes: NDArray[np.complex128], ell: float, layout: NDArray[np.intp] | None = None
) -> NDArray[np.complex128]:
    """`shapes` with the rotations (the layout's ``theta_x``, ``theta_y`` dofs; ``4 i + 2``,
    ``4 i + 3`` by default) multiplied by `ell`."""
    out = shapes.copy()
    if layout is None:
        out[2::4] *= ell
        out[3::4] *= ell
        return out
    cols = [c for c in (2, 3, 5) if c < np.shape(layout)[1]]  # theta_x, theta_y, theta
    rot = np.asarray(layout)[:, cols].ravel()
    out[rot[rot >= 0]] *= ell
    return out


def _mac(
    a: NDArray[np.complex128],
    b: NDArray[np.complex128],
    ell: float,
    layout: NDArray[np.intp] | None = None,
) -> NDArray[np.float64]:
    """``|a_i^H b_j|^2 / (|a_i|^2 |b_j|^2)`` for every pair of columns, rotations weighted by
    `ell` (clipped to 1 against round-off)."""
    a, b = _weighted(a, ell, layout), _weighted(b, ell, layout)
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return np.minimum(num / den, 1.0)


def _mac_columns(
    a: NDArray[np.complex128],
    b: NDArray[np.complex128],
    ell: float,
    layout: NDArray[np.intp] | None = None,
) -> NDArray[np.float64]:
    """:func:`_mac` of the pairs of columns ``(a_j, b_j)`` only."""
    a, b = _weighted(a, ell, layout), _weighted(b, ell, layout)
    num = np.abs(np.sum(a.conj() * b, axis=0)) ** 2
    den = np.sum(np.abs(a) ** 2, axis=0) * np.sum(np.abs(b) ** 2, axis=0)
    return np.minimum(num / den, 1.0)


def _orbit_forms(
    v: NDArray[np.complex128], ell: float, nodes: NDArray[np.intp]
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Hermitian forms ``(H, N)`` on the columns of `v`: the signed orbit area
    ``sum_nodes -Im(conj(X) Y) + ell^2 Im(conj(Theta_y) Theta_x)`` and the amplitude
    ``sum |X|^2 + |Y|^2 + ell^2 (|Theta_x|^2 + |Theta_y|^2)`` (see :func:`_whirl`)."""
    g = _gather(v, nodes)
    x, y, tx, ty = g[:, 0], g[:, 1], g[:, 2], g[:, 3]
    h = 0.5j * (x.conj().T @ y - y.conj().T @ x) + 0.5j * ell**2 * (
        ty.conj().T @ tx - tx.conj().T @ ty
    )
    g = x.conj().T @ x + y.conj().T @ y + ell**2 * (tx.conj().T @ tx + ty.conj().T @ ty)
    return (h + h.conj().T) / 2, (g + g.conj().T) / 2


def _circular_pairs(
    lam: NDArray[np.complex128],
    shapes: NDArray[np.complex128],
    ell: float,
    nodes: NDArray[np.intp],
) -> NDArray[np.complex128]:
    """Within each cluster of equal eigenvalues (an axisymmetric rotor's pairs), choose the
    basis that extremises the orbit area: circular backward and forward orbits, not an
    arbitrary mix; shapes rescaled as in :func:`_complex_modes`."""
    import scipy.linalg

    out = shapes.copy()
    i = 0
    while i < lam.size:
        j = i
        while j + 1 < lam.size and abs(lam[j + 1] - lam[i]) <= CLUSTER_RTOL * abs(lam[i]):
            j += 1
        if j > i:
            v = out[:, i : j + 1]
            h, g = _orbit_forms(v, ell, nodes)
            _, c = scipy.linalg.eigh(h, g)
            out[:, i : j + 1] = _normalise(v @ c, nodes)
        i = j + 1
    return out


def _normalise(
    vec: NDArray[np.complex128], nodes: NDArray[np.intp] | None = None
) -> NDArray[np.complex128]:
    """Scale each column so that its translation of largest magnitude is 1 (all dofs if no
    translation moves); translations: the `nodes` layout's x and y (``4 i``, ``4 i + 1``
    by default)."""
    n = vec.shape[0]
    trans = np.zeros(n, dtype=bool)
    if nodes is None:
        trans[0::4] = trans[1::4] = True
    else:
        t = np.asarray(nodes)[:, :2].ravel()
        trans[t[t >= 0]] = True
    out = vec.copy()
    for j in range(vec.shape[1]):
        v = vec[:, j]
        ref = np.where(trans, np.abs(v), 0.0)
        if ref.max() <= 1e-12 * np.abs(v).max():
            ref = np.abs(v)
        out[:, j] = v / v[int(np.argmax(ref))]
    return out


def _whirl(nodes: NDArray[np.complex128], ell: float) -> str:
    """Whirl sense of one mode from its node amplitudes ``(X, Y, Theta_x, Theta_y)``.

    A node orbits forward when its signed orbit area ``-Im(conj(X) Y)`` is positive (for
    ``x = Re(X e^{i w t})``, ``y = Re(Y e^{i w t})``, ``w > 0``: counter-clockwise from +x to
    +y, the spin's sense); tilts count through the axis direction ``(theta_y, -theta_x)``,
    weighted by ``ell^2`` (the mean element length).
    """
    X, Y, Tx, Ty = nodes.T
    area = -np.imag(np.conj(X) * Y) + ell**2 * np.imag(np.conj(Ty) * Tx)
    amp = np.abs(X) ** 2 + np.abs(Y) ** 2 + ell**2 * (np.abs(Tx) ** 2 + np.abs(Ty) ** 2)
    moving = amp >= NODE_RTOL * amp.max()
    signed = moving & (np.abs(area) > PLANAR_RTOL * amp)
    if not signed.any():
        return "planar"
    if np.all(area[signed] > 0.0):
        return "forward"
    if np.all(area[signed] < 0.0):
        return "backward"
    return "mixed"
