"""glassscan: a physically based simulator of a laser-line triangulation sensor
(scanCONTROL 2600-100 class, 658 nm) looking at glass, and the localisation pipeline of
Adrian & Pham (Border Identifier Points registered by ICP).

The Rust library is the one implementation: this package calls it, with the same checks and
messages as the ``glassscan`` command line.

    >>> import glassscan
    >>> scene = glassscan.Scene.load("scenes/edge_study_bare.toml", scan_angle_deg=45)
    >>> sim = scene.simulate(pose=0, photons=2**16, seed=1)
    >>> sim.image.shape, sim.image.dtype          # digital numbers, row 0 at the top
    ((832, 640), dtype('uint16'))
    >>> sim.profile["z_mm"][sim.profile["valid"]]  # the profile, a numpy structured array
"""

from ._native import DEFAULT_PHOTONS, GlassscanError, InputError, __version__
from ._files import read_ideal_profile, read_image, read_irradiance, read_points, read_profile
from ._dataset import Dataset
from ._scene import Scene, Simulation, locate, register
from ._tables import IDEAL_PROFILE_DTYPE, PATH_CLASSES, PROFILE_DTYPE

__all__ = [
    "DEFAULT_PHOTONS",
    "Dataset",
    "GlassscanError",
    "IDEAL_PROFILE_DTYPE",
    "InputError",
    "PATH_CLASSES",
    "PROFILE_DTYPE",
    "Scene",
    "Simulation",
    "__version__",
    "locate",
    "read_ideal_profile",
    "read_image",
    "read_irradiance",
    "read_points",
    "read_profile",
    "register",
]
