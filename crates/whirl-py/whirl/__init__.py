"""whirl: rotordynamics of rotors on rolling-element bearings, from Python.

The Python face of the whirl library: the same model files, the same analyses with the
command line's options as keyword arguments and its defaults, results whose arrays are
numpy arrays, ``to_pandas()`` for the tables the command line writes as CSV and
``to_dict()`` for what it writes as summary.json.

    >>> import whirl
    >>> model = whirl.Model.from_file("examples/reference_rotor.toml")
    >>> diagram = whirl.campbell(model, speeds="0:800Hz:161")
    >>> diagram.to_pandas().head()

A model is read from a model file, TOML text or a dict of its tables, or built in code from
parts, one per table of the model file: ``whirl.Model.build("rotor", [whirl.Shaft(...),
whirl.Disk(...), whirl.Bearing(...)])`` (:mod:`whirl.parts`).

Speeds are given with their unit as text (``"50Hz"``, ``"0:800Hz:161"``, ``"3000rpm"``) or
as numbers in rad/s (SI, as everywhere in the model file).
"""

from ._whirl import BUILD_ID, InputError, NumericalError, WhirlError, __version__
from .analyses import fit_forcing, frf, reduce, static, stiffness, ucs
from .hbm import hbm
from .nsv_map import map  # noqa: A004 - the command's name
from .model import Model, WhirlWarning
from .modal import (
    CampbellResult,
    CheckResult,
    ConvergenceResult,
    ModalResult,
    campbell,
    check,
    convergence,
    modal,
)
from .nsv import CascadeResult, cascade
from .parts import (
    BallBearing,
    Bearing,
    Damping,
    Defect,
    Disk,
    Elements,
    Housing,
    Material,
    Operating,
    RollerBearing,
    Shaft,
    SqueezeFilm,
    Unbalance,
    Waviness,
)
from .report import Report
from .response import UnbalanceResult, unbalance
from .ross import from_ross, read_ross
from .runup import runup
from .study import StudyResult, study
from .time import SimulationResult, simulate

__all__ = [
    "BUILD_ID",
    "BallBearing",
    "Bearing",
    "CampbellResult",
    "CascadeResult",
    "CheckResult",
    "ConvergenceResult",
    "Damping",
    "Defect",
    "Disk",
    "Elements",
    "Housing",
    "InputError",
    "Material",
    "ModalResult",
    "Model",
    "NumericalError",
    "Operating",
    "Report",
    "RollerBearing",
    "Shaft",
    "SimulationResult",
    "SqueezeFilm",
    "StudyResult",
    "Unbalance",
    "UnbalanceResult",
    "Waviness",
    "WhirlError",
    "WhirlWarning",
    "__version__",
    "campbell",
    "cascade",
    "check",
    "convergence",
    "fit_forcing",
    "frf",
    "from_ross",
    "hbm",
    "map",
    "modal",
    "read_ross",
    "reduce",
    "runup",
    "simulate",
    "static",
    "stiffness",
    "study",
    "ucs",
    "unbalance",
]
