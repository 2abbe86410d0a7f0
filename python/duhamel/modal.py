"""Modal bases: the mass-normalised undamped modes of ``(K, M)`` and their modal damping.

:class:`ModalBasis` is what :meth:`duhamel.System.modal` returns and what a run is integrated
on. A basis can also come from elsewhere, :meth:`ModalBasis.from_modes` (modes computed by an
FE package, validated), be kept on disk (:meth:`ModalBasis.save`, :meth:`ModalBasis.load`:
``.npz``, bit for bit) and be shared by several systems with the same ``M`` and ``K``
(:meth:`duhamel.System.use_basis`), each deriving its own modal damping from the undamped
modes (docs/basis.md).
"""

from __future__ import annotations

import os
import zipfile
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from duhamel._engine.validate import as_float_array, as_square_matrix, issparse, positive_float

__all__ = ["ModalBasis"]

#: Relative size of off-diagonal modal damping terms above which C is "non-classical".
CLASSICAL_RTOL = 1e-8
#: What :meth:`ModalBasis.save` writes in its ``format`` entry, and the version of its layout.
FILE_FORMAT = "duhamel.ModalBasis"
FILE_VERSION = 1
_FIELDS = ("phi", "omega2", "omega", "c", "zeta")


@dataclass(frozen=True, eq=False)
class ModalBasis:
    """Mass-normalised undamped modes of a :class:`~duhamel.System` and their modal damping.

    Each modal coordinate obeys ``q_i'' + c_i q_i' + omega2_i q_i = phi_i^T f(t)``.
    All arrays are read-only float64. Made by :meth:`duhamel.System.modal`, from modes
    computed elsewhere by :meth:`from_modes`, or read back by :meth:`load`.

    Attributes
    ----------
    phi : ndarray, shape (n_dof, n_modes)
        Mode shapes (C-contiguous), normalised so that ``phi.T @ M @ phi = I``. The entry of
        largest magnitude of each mode is positive (the first one, in case of near-ties).
    omega2 : ndarray, shape (n_modes,)
        Squared natural frequencies (rad/s)^2, ascending, >= 0. Rigid-body modes are exactly 0.
    omega : ndarray, shape (n_modes,)
        Natural frequencies ``sqrt(omega2)`` in rad/s.
    c : ndarray, shape (n_modes,)
        Modal damping per unit modal mass, the coefficient ``2 zeta omega`` of ``q'``. This is
        the authoritative damping value: for a rigid-body mode (``omega == 0``) the damping
        lives here only (e.g. ``c = alpha`` with Rayleigh damping ``(alpha, beta)``).
    zeta : ndarray, shape (n_modes,)
        Damping ratios ``c / (2 omega)`` where ``omega > 0``, else 0.0.
    c_coupling : ndarray, shape (n_modes, n_modes), or None
        For a damping matrix `C` that the undamped modes do not diagonalise (non-classical
        damping): the off-diagonal part of ``phi.T @ C @ phi``. The integrators keep the
        diagonal in the exact background and treat this remainder as a modal pseudo-force.
        None for classical damping.

    Examples
    --------
    >>> import numpy as np
    >>> from duhamel.system import System
    >>> basis = System(np.eye(2), [[2.0, -1.0], [-1.0, 2.0]], zeta=0.05).modal()
    >>> basis.n_modes, basis.omega2.tolist()
    (2, [1.0, 3.0])
    >>> basis.zeta.tolist()
    [0.05, 0.05]
    """

    phi: NDArray[np.float64]
    omega2: NDArray[np.float64]
    omega: NDArray[np.float64]
    c: NDArray[np.float64]
    zeta: NDArray[np.float64]
    c_coupling: NDArray[np.float64] | None = None
    #: The mass matrix the modes are normalised with, and the dof labels, when known (for
    #: :meth:`participation`); not saved by :meth:`save`.
    mass: Any = field(default=None, repr=False)
    labels: Any = field(default=None, repr=False)
    stiffness: str = field(default="", repr=False)  # which, as summary() states ("": K)

    def participation(self, direction: ArrayLike | str, *, M: Any = None) -> Any:
        """Participation factors, effective modal masses and mass ratios in a direction.

        Parameters
        ----------
        direction : array_like or str
            The influence vector ``r`` over the dofs (ones on the dofs that move with a unit
            support displacement), or a direction label such as ``"ux"``: ones on the dofs
            labelled ``(node, "ux")`` or whose name ends in ``"ux"``.
        M : array_like or sparse, optional
            The mass matrix, for a basis that does not know it (read by :meth:`load`).

        Returns
        -------
        duhamel.participation.Participation
            ``factors``, ``effective_mass``, ``ratio``, ``cumulative`` (one value per mode)
            and ``total_mass`` ``r^T M r``, which the effective masses of every mode sum to.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> K = [[2.0, -1.0], [-1.0, 1.0]]
        >>> p = duhamel.System(np.eye(2), K).modal().participation(np.ones(2))
        >>> round(float(p.effective_mass.sum()), 12), round(float(p.cumulative[0]), 4)
        (2.0, 0.9472)
        """
        from duhamel.participation import participation

        mass = self.mass if M is None else M
        if mass is None:
            raise ValueError("`M` must be given: this basis does not hold its mass matrix")
        return participation(np.asarray(self.phi), mass, direction, self.labels)

    def summary(self, directions: str | NDArray[np.float64] | list[Any] | None = None) -> str:
        """A table of the modes: ``omega``, period, damping ratio and, per direction
        (a label or a vector; default: ``"ux"``, ``"uy"``, ``"uz"`` where the labels have
        them), the effective mass ratio and its cumulative value, in %; first, which
        stiffness the modes are of, for a model with force elements (:meth:`System.modal`).

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> basis = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]]).modal()
        >>> print(basis.summary(np.ones(2)).splitlines()[1].split()[-2:])
        ['94.72', '94.72']
        """
        from duhamel.participation import labelled, summary_table

        if directions is None:  # the labelled directions that move mass
            directions = [d for d in ("ux", "uy", "uz") if labelled(self.labels, d)]
            directions = [d for d in directions if self.participation(d).total_mass > 0]
        elif isinstance(directions, str | np.ndarray):
            directions = [directions]
        parts = {
            (d if isinstance(d, str) else f"r{k}"): self.participation(d)
            for k, d in enumerate(directions)
        }
        table = summary_table(np.asarray(self.omega), np.asarray(self.zeta), parts)
        return f"modes of {self.stiffness}\n{table}" if self.stiffness else table

    @property
    def n_modes(self) -> int:
        """Number of modes in the basis."""
        return int(self.omega2.shape[0])

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom of the mode shapes."""
        return int(self.phi.shape[0])

    @classmethod
    def from_modes(
        cls, phi: ArrayLike, omega: ArrayLike, M: Any, *, rtol: float = 1e-6
    ) -> ModalBasis:
        """An undamped basis from modes computed elsewhere (an FE package, a previous run).

        Parameters
        ----------
        phi : array_like, shape (n_dof, n_modes)
            Mode shapes, one per column, normalised to unit modal mass (``phi.T M phi = I``).
        omega : array_like, shape (n_modes,)
            Natural frequencies in rad/s (not Hz), >= 0; 0 for rigid-body modes.
        M : array_like or scipy.sparse matrix, shape (n_dof, n_dof)
            The mass matrix the modes are normalised with.
        rtol : float
            Largest accepted ``max |phi.T M phi - I|``.

        Returns
        -------
        ModalBasis
            The modes sorted by ascending `omega` (columns reordered if needed), each signed
            so that its entry of largest magnitude is positive (an exact negation), with
            ``omega2 = omega**2`` and no damping (``c = zeta = 0``): a
            :class:`~duhamel.System` given it with :meth:`~duhamel.System.use_basis` derives
            its own damping.

        Raises
        ------
        TypeError
            If an argument is not real numeric data (or `phi` is sparse).
        ValueError
            If the shapes disagree, an entry is NaN or inf, a frequency is negative, or the
            modes are not mass-orthonormal to `rtol`.

        Examples
        --------
        >>> import numpy as np, duhamel
        >>> M = np.diag([2.0, 2.0])
        >>> phi = np.array([[1.0, 1.0], [1.0, -1.0]]) / 2.0   # unit modal mass
        >>> basis = duhamel.ModalBasis.from_modes(phi, [1.0, 2.0], M)
        >>> basis.omega2.tolist(), basis.c.tolist()
        ([1.0, 4.0], [0.0, 0.0])
        """
        rtol = positive_float(rtol, "rtol")
        phi = as_float_array(phi, "phi", ndim=2)
        n_dof, n_modes = phi.shape
        if n_modes == 0 or n_modes > n_dof:
            raise ValueError(
                f"`phi` must hold between 1 and n_dof = {n_dof} modes (columns), got {n_modes}"
            )
        omega = as_float_array(omega, "omega", ndim=1)
        if omega.size != n_modes:
            raise ValueError(
                f"`omega` must have one entry per mode (column of `phi`): {n_modes}, got "
                f"{omega.size}"
            )
        negative = np.flatnonzero(omega < 0.0)
        if negative.size:
            i = int(negative[0])
            raise ValueError(
                f"`omega` must be >= 0 (natural frequencies in rad/s), got omega[{i}] = "
                f"{omega[i]:.6g}"
            )
        M = as_square_matrix(M, "M", n=n_dof, ref="`phi` (n_dof rows)")
        error, (i, j) = orthonormality_error(phi, M)
        if error > rtol:
            raise ValueError(
                f"`phi` must be mass-orthonormal, phi.T @ M @ phi = I, but entry ({i}, {j}) is "
                f"off by {error:.3g} > `rtol` = {rtol:g}: scale each mode by "
                "1/sqrt(phi_i^T M phi_i) (modes normalised otherwise, e.g. to a largest entry "
                "of 1, must be rescaled), or pass a larger `rtol` for modes known to fewer digits"
            )
        order = np.argsort(omega, kind="stable")
        if np.any(order != np.arange(n_modes)):
            phi, omega = phi[:, order], omega[order]
        zeros = np.zeros(n_modes)
        return cls(
            phi=frozen(fix_signs(phi)),
            omega2=frozen(omega * omega),
            omega=frozen(omega),
            c=frozen(zeros),
            zeta=frozen(zeros),
            mass=M,
        )

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the basis to `path` (an ``.npz`` archive; the name is used as given).

        Every array is stored as it is, so :meth:`load` gives it back bit for bit. The
        archive also records the format name and version.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write (overwritten if it exists).

        Examples
        --------
        >>> import numpy as np, tempfile, pathlib, duhamel
        >>> basis = duhamel.System(np.eye(2), [[2.0, -1.0], [-1.0, 2.0]]).modal()
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "basis.npz"
        >>> basis.save(path)
        >>> np.array_equal(duhamel.ModalBasis.load(path).phi, basis.phi)
        True
        """
        arrays = {name: getattr(self, name) for name in _FIELDS}
        if self.c_coupling is not None:
            arrays["c_coupling"] = self.c_coupling
        with open(path, "wb") as file:  # np.savez(path) would append ".npz" to a bare name
            np.savez(file, format=np.array(FILE_FORMAT), version=np.array(FILE_VERSION), **arrays)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> ModalBasis:
        """Read a basis written by :meth:`save`.

        Parameters
        ----------
        path : str or os.PathLike
            The ``.npz`` file.

        Returns
        -------
        ModalBasis
            The saved basis, every array bit for bit as it was saved.

        Raises
        ------
        FileNotFoundError
            If `path` does not exist.
        ValueError
            If the file is not a basis written by :meth:`save` (not an ``.npz`` archive,
            another format, a newer version, missing or inconsistent arrays).

        Examples
        --------
        >>> import numpy as np, tempfile, pathlib, duhamel
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "chain.npz"
        >>> duhamel.System(np.eye(2), np.eye(2), zeta=0.1).modal().save(path)
        >>> duhamel.ModalBasis.load(path).zeta.tolist()
        [0.1, 0.1]
        """
        try:
            archive = np.load(path, allow_pickle=False)
        except FileNotFoundError:
            raise
        except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
            raise _not_a_basis(path, f"numpy cannot read it ({exc})") from None
        if not isinstance(archive, np.lib.npyio.NpzFile):
            raise _not_a_basis(path, "it holds a single array, not an .npz archive")
        with archive:
            try:
                entries = {name: archive[name] for name in archive.files}
            except (OSError, ValueError, zipfile.BadZipFile) as exc:
                raise _not_a_basis(path, f"an entry cannot be read ({exc})") from None
        fmt = entries.get("format")
        if fmt is None or fmt.shape != () or fmt.dtype.kind != "U" or str(fmt) != FILE_FORMAT:
            raise _not_a_basis(path, f"it has no 'format' entry {FILE_FORMAT!r}")
        version = entries.get("version")
        if version is None or version.shape != () or version.dtype.kind not in "iu":
            raise _not_a_basis(path, "it has no integer 'version' entry")
        if int(version) > FILE_VERSION:
            raise ValueError(
                f"{os.fspath(path)!r} holds a ModalBasis of format version {int(version)}, "
                f"newer than this duhamel reads ({FILE_VERSION}): update duhamel"
            )
        missing = [name for name in _FIELDS if name not in entries]
        if missing:
            raise _not_a_basis(path, f"it lacks the array(s) {', '.join(missing)}")
        arrays = {name: entries[name] for name in _FIELDS}
        if "c_coupling" in entries:
            arrays["c_coupling"] = entries["c_coupling"]
        problem = _layout_problem(arrays)
        if problem:
            raise _not_a_basis(path, problem)
        return cls(**{name: frozen(a) for name, a in arrays.items()})


def _not_a_basis(path: Any, why: str) -> ValueError:
    return ValueError(
        f"{os.fspath(path)!r} is not a duhamel ModalBasis file (written by ModalBasis.save): {why}"
    )


def _layout_problem(arrays: dict[str, NDArray[Any]]) -> str | None:
    """Why the arrays of a loaded basis do not make one (None when they do)."""
    for name, a in arrays.items():
        if a.dtype != np.float64:
            return f"'{name}' has dtype {a.dtype}, not float64"
        if not np.all(np.isfinite(a)):
            return f"'{name}' contains NaN or inf"
    phi = arrays["phi"]
    if phi.ndim != 2 or not 1 <= phi.shape[1] <= phi.shape[0]:
        return f"'phi' has shape {phi.shape}, not (n_dof, n_modes) with 1 <= n_modes <= n_dof"
    n = phi.shape[1]
    for name in _FIELDS[1:]:
        if arrays[name].shape != (n,):
            return f"'{name}' has shape {arrays[name].shape}, not ({n},)"
    coupling = arrays.get("c_coupling")
    if coupling is not None and coupling.shape != (n, n):
        return f"'c_coupling' has shape {coupling.shape}, not ({n}, {n})"
    if np.any(arrays["omega2"] < 0.0) or np.any(arrays["omega"] < 0.0):
        return "a frequency is negative"
    return None


def frozen(a: ArrayLike) -> NDArray[np.float64]:
    """A read-only C-contiguous float64 copy of `a` (values unchanged)."""
    out = np.ascontiguousarray(a, dtype=np.float64)
    if out is a or out.base is not None:
        out = out.copy()
    out.setflags(write=False)
    return out


def fix_signs(phi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Make the (first near-)largest-magnitude entry of each column positive."""
    mag = np.abs(phi)
    idx = np.argmax(mag >= (1.0 - 1e-6) * mag.max(axis=0), axis=0)
    signs = np.sign(phi[idx, np.arange(phi.shape[1])])
    signs[signs == 0.0] = 1.0
    return phi * signs


def orthonormality_error(phi: NDArray[np.float64], M: Any) -> tuple[float, tuple[int, int]]:
    """``max |phi.T M phi - I|`` and the entry where it is reached."""
    gram = phi.T @ np.asarray(M @ phi)
    gram = np.abs(gram - np.eye(gram.shape[0]))
    i, j = np.unravel_index(int(np.argmax(gram)), gram.shape)
    return float(gram[i, j]), (int(i), int(j))


def backward_errors(
    phi: NDArray[np.float64], omega2: NDArray[np.float64], M: Any, K: Any
) -> NDArray[np.float64]:
    """Normwise backward error of each eigenpair of ``K phi = omega2 M phi``:
    ``|K phi_i - omega2_i M phi_i| / ((|K| + omega2_i |M|) |phi_i|)`` (vector 2-norms, matrix
    infinity norms, which bound the 2-norm of a symmetric matrix)."""

    def norm(a: Any) -> float:
        return float(abs(a).sum(axis=1).max()) if issparse(a) else float(np.abs(a).sum(1).max())

    residual = np.asarray(K @ phi) - np.asarray(M @ phi) * omega2
    scale = (norm(K) + omega2 * norm(M)) * np.linalg.norm(phi, axis=0)
    return np.linalg.norm(residual, axis=0) / np.maximum(scale, np.finfo(float).tiny)


class Damping(Protocol):
    """What :func:`damped` reads of a system: its matrices and damping as given."""

    @property
    def M(self) -> Any: ...
    @property
    def K(self) -> Any: ...
    @property
    def C(self) -> Any: ...
    @property
    def damping(self) -> str: ...
    @property
    def zeta(self) -> Any: ...
    @property
    def rayleigh(self) -> tuple[float, float] | None: ...


def damped(lam: NDArray[np.float64], phi: NDArray[np.float64], system: Damping) -> ModalBasis:
    """The basis of `system` on the undamped modes ``(lam, phi)`` (mass-normalised, ascending):
    its modal damping, and for a damping matrix the modes rotated within degenerate clusters
    so that a classical C comes out diagonal, with any non-classical remainder."""
    n = lam.size
    kind = system.damping
    if kind == "matrix":
        lam, phi = _diagonalise_clusters(lam, phi, system)
    elif kind == "rayleigh":
        alpha, beta = system.rayleigh  # type: ignore[misc]
        c = alpha + beta * lam
    elif kind == "zeta":
        z = system.zeta
        if callable(z):  # a function of the circular frequency
            z = _zeta_of(z, np.sqrt(np.maximum(lam, 0.0)))
        if isinstance(z, np.ndarray) and z.size != n:
            raise ValueError(
                f"`zeta` has {z.size} entries but the modal basis has {n} modes; "
                "pass one damping ratio per retained mode"
            )
        c = 2.0 * np.asarray(z) * np.sqrt(lam)
    else:
        c = np.zeros(n)
    phi = fix_signs(phi)
    coupling = None
    if kind == "matrix":
        cm = phi.T @ np.asarray(system.C @ phi)
        cm = (cm + cm.T) / 2
        c = np.diag(cm).copy()
        off = cm - np.diag(c)
        ref = max(float(np.max(np.abs(c))), np.finfo(float).tiny)
        if n > 1 and float(np.max(np.abs(off))) > CLASSICAL_RTOL * ref:
            coupling = frozen(off)
    omega = np.sqrt(lam)
    zeta = np.divide(c, 2.0 * omega, out=np.zeros(n), where=omega > 0.0)
    return ModalBasis(
        phi=frozen(phi),
        omega2=frozen(lam),
        omega=frozen(omega),
        c=frozen(np.broadcast_to(c, (n,))),
        zeta=frozen(zeta),
        c_coupling=coupling,
        mass=getattr(system, "M", None),
        labels=getattr(system, "dof_labels", None),
    )


def _zeta_of(zeta: Any, omega: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per-mode ratios from `zeta` given as a function of the circular frequency."""
    z = np.asarray(zeta(omega), dtype=np.float64)
    z = np.broadcast_to(z, omega.shape) if z.ndim == 0 else z
    if z.shape != omega.shape or not np.all(np.isfinite(z)):
        raise ValueError(
            f"`zeta` (a function of omega) must return one finite ratio per mode "
            f"({omega.size}), got shape {z.shape}"
        )
    return z


def _diagonalise_clusters(
    lam: NDArray[np.float64], phi: NDArray[np.float64], system: Damping
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rotate the modes within clusters of (numerically) equal frequency, which may be mixed
    freely, so that the projection of C is diagonal there."""
    mass = np.asarray(system.M.diagonal())
    ratio = np.abs(np.asarray(system.K.diagonal()))[mass > 0] / mass[mass > 0]
    scale = max(float(np.max(np.abs(lam))), float(np.max(ratio)))
    cm = phi.T @ np.asarray(system.C @ phi)
    cm = (cm + cm.T) / 2
    lam, phi = lam.copy(), phi.copy()
    n, i = lam.size, 0
    while i < n:
        j = i
        while j + 1 < n and lam[j + 1] - lam[j] <= 1e-8 * lam[j + 1] + 1e-13 * scale:
            j += 1
        if j > i:
            import scipy.linalg

            _, y = scipy.linalg.eigh(cm[i : j + 1, i : j + 1])
            phi[:, i : j + 1] = phi[:, i : j + 1] @ y
            lam[i : j + 1] = lam[i : j + 1].mean()
        i = j + 1
    return lam, phi
