"""Rotor models: Timoshenko shafts, rigid disks and bearings assembled into a duhamel System.

SI units. Four degrees of freedom per node, ``(x, y, theta_x, theta_y)``: node ``i`` owns
``4 i .. 4 i + 3``; the shaft axis is z, shaft ``i`` joins nodes ``i`` and ``i + 1``, rotations
are right-handed about x and y, the shaft spins about +z, and forward whirl turns from +x to +y
(Friswell et al., *Dynamics of Rotating Machines*, 2010). See docs/rotor.md.

Examples
--------
>>> import numpy as np, duhamel
>>> from duhamel import rotor as R
>>> model = R.Rotor([R.Shaft(0.3, 0.05, material=R.STEEL)] * 4,
...                 [R.Disk(2, mass=20.0, Ip=0.2, Id=0.1)],
...                 [R.Bearing(0, 1e7, 1e7), R.Bearing(4, 1e7, 1e7)], zeta=0.02)
>>> system = model.system(R.rpm(3000), [R.Unbalance(2, m_e=1e-4), R.Gravity()])
>>> sol = duhamel.solve(system, duhamel.Semianalytic(modes=10), t_end=0.05, dt=1e-4)
>>> sol.x.shape
(501, 20)
"""

from duhamel.elements import BreathingCrack
from duhamel.rotor._plot_response import (
    plot_bode,
    plot_mode_shape,
    plot_polar,
    plot_spectrogram,
    spectrogram,
)
from duhamel.rotor._speed import constant_speed, rpm
from duhamel.rotor.assembly import RotorMatrices
from duhamel.rotor.bearing import Bearing
from duhamel.rotor.campbell import Campbell
from duhamel.rotor.controllers import (
    PID,
    Amplifier,
    LowPass,
    Notch,
    Sensor,
    Series,
    StateSpace,
)
from duhamel.rotor.critical_map import CriticalSpeedMap, Intersection
from duhamel.rotor.disk import Disk
from duhamel.rotor.dofs import DIRECTIONS
from duhamel.rotor.frequency import FrequencyResponse, FrequencyResponseMap
from duhamel.rotor.journal import ShortJournalBearing
from duhamel.rotor.loads import Gravity, RotorLoad, SuddenForce, Unbalance, VectorStep
from duhamel.rotor.magnetic import ClosedLoop, MagneticBearing
from duhamel.rotor.material import STEEL, Material
from duhamel.rotor.misalignment import CouplingMisalignment
from duhamel.rotor.model import Rotor
from duhamel.rotor.modes import Modes
from duhamel.rotor.plot import plot_campbell, plot_orbit
from duhamel.rotor.ross import RossDofs, RossModel, RossRotor, from_ross
from duhamel.rotor.shaft import Shaft, cowper_shear_coefficient
from duhamel.rotor.stability import Level1Stability, Stage, anticipated_cross_coupling
from duhamel.rotor.torsion import Torsion, TorsionalCoupling, TorsionalModes
from duhamel.rotor.unbalance import Peak, UnbalanceResponse, unbalance_response

__all__ = [
    "DIRECTIONS",
    "PID",
    "STEEL",
    "Amplifier",
    "Bearing",
    "BreathingCrack",
    "Campbell",
    "ClosedLoop",
    "CouplingMisalignment",
    "CriticalSpeedMap",
    "Disk",
    "FrequencyResponse",
    "FrequencyResponseMap",
    "Gravity",
    "Intersection",
    "Level1Stability",
    "LowPass",
    "MagneticBearing",
    "Material",
    "Modes",
    "Notch",
    "Peak",
    "RossDofs",
    "RossModel",
    "RossRotor",
    "Rotor",
    "RotorLoad",
    "RotorMatrices",
    "Sensor",
    "Series",
    "Shaft",
    "ShortJournalBearing",
    "Stage",
    "StateSpace",
    "SuddenForce",
    "Torsion",
    "TorsionalCoupling",
    "TorsionalModes",
    "Unbalance",
    "UnbalanceResponse",
    "VectorStep",
    "anticipated_cross_coupling",
    "constant_speed",
    "cowper_shear_coefficient",
    "from_ross",
    "plot_bode",
    "plot_campbell",
    "plot_mode_shape",
    "plot_orbit",
    "plot_polar",
    "plot_spectrogram",
    "rpm",
    "spectrogram",
    "unbalance_response",
]
