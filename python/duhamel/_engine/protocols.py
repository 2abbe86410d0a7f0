"""What loads, elements and mass laws need of the model they are added to.

:class:`duhamel.System` satisfies :class:`Model`; :mod:`duhamel.loads` and
:mod:`duhamel.elements` are annotated with it rather than with ``System``, so they need not
import :mod:`duhamel.system` (which imports them): the dependency runs one way only.
"""

from __future__ import annotations

from typing import Any, Protocol

__all__ = ["Model"]


class Model(Protocol):
    """A discretised model as loads and elements see it: its size and its mass matrix.

    Examples
    --------
    >>> import numpy as np, duhamel
    >>> from duhamel._engine.protocols import Model
    >>> def size(model: Model) -> int:
    ...     return model.n_dof
    >>> size(duhamel.System(np.eye(3), np.eye(3)))
    3
    """

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom."""
        ...

    @property
    def M(self) -> Any:
        """Mass matrix, ``(n_dof, n_dof)``: a dense array or a scipy.sparse matrix."""
        ...
