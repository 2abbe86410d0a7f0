"""ROSS interoperability (optional extra ``[ross]``): a duhamel model from a ROSS ``Rotor``.

* :mod:`duhamel.rotor.ross.model`: :func:`from_ross` and the :class:`RossModel` it returns;
* :mod:`duhamel.rotor.ross.dofs`: ROSS's lateral matrices and the dof map :class:`RossDofs`;
* :mod:`duhamel.rotor.ross.analyses`: :class:`RossRotor`, a native rotor's analyses on ROSS's
  matrices re-evaluated at each speed;
* :mod:`duhamel.rotor.ross.runup`: ROSS's frequency-dependent bearings and seals following a
  speed law.

ROSS is imported only by the caller (never here). See docs/ross.md.
"""

from duhamel.rotor.ross.analyses import RossRotor
from duhamel.rotor.ross.dofs import RossDofs, lateral_matrices
from duhamel.rotor.ross.model import RossModel, from_ross

__all__ = ["RossDofs", "RossModel", "RossRotor", "from_ross", "lateral_matrices"]
