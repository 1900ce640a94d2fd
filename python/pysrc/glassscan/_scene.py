"""Scenes, their simulation at a scan pose, and the localisation commands (``locate``,
``register``) with the command line's results."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Union

import numpy as np

from . import _native
from ._tables import ideal_table, profile_table

PathLike = Union[str, "os.PathLike[str]"]


def _whole(name: str, value: Any, most: int = 2**64 - 1) -> int:
    """``value`` as a whole number in 0..=``most`` for the native layer, or an InputError
    naming ``name`` (a float such as ``1e6`` or ``2.5`` is refused rather than truncated)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise _native.InputError(f"{name} must be a whole number, got {value!r}")
    if not 0 <= int(value) <= most:
        raise _native.InputError(f"{name} must be in 0..={most}, got {value}")
    return int(value)


def _threshold(threshold: Union[int, str, None]) -> Optional[str]:
    return None if threshold is None else str(threshold)


def _poses_to_arrays(value: Any) -> Any:
    """Every ``matrix_mm`` (row-major list of 16) in a command's JSON as a 4 × 4 array."""
    if isinstance(value, dict):
        out = {k: _poses_to_arrays(v) for k, v in value.items()}
        if isinstance(out.get("matrix_mm"), list) and len(out["matrix_mm"]) == 16:
            out["matrix_mm"] = np.array(out["matrix_mm"], dtype=float).reshape(4, 4)
        return out
    if isinstance(value, list):
        return [_poses_to_arrays(v) for v in value]
    return value


@dataclass
class Simulation:
    """What the sensor produced at one scan pose, and its ground truth.

    Attributes:
        image: digital numbers (uint16, rows × columns, row 0 at the top); the PNG of
            ``glassscan scan`` holds them shifted left by 16 − adc_bits.
        irradiance: W/m² on the image plane (float32, as the EXR stores it): ``total`` and
            one image per path class (``glass_edge``, ``table``, ``through_glass``, …).
        profile: the firmware's profile, a structured array of
            :data:`glassscan.PROFILE_DTYPE` (the columns of the profile CSV).
        ground_truth: ``sensor_pose``, ``flange_pose``, ``mount``, ``target_pose``,
            ``target_nominal_pose`` (4 × 4, mm; p_parent = M @ [p, 1]), ``edge_point_mm``
            (p_e in the base frame, or None if the laser plane misses the border),
            ``edge_point_sensor_mm`` (x, z), ``ideal_profile`` (a structured array: the
            first hit of each fan ray), and the pose's index, border fraction, scan angle,
            exposure and wavelength.
        saturated_pixels: pixels at the full well or the ADC's full scale.
        warnings: why the pose may be physically empty or meaningless.
        stats: the light transport's counters.
    """

    image: np.ndarray
    irradiance: Dict[str, np.ndarray]
    profile: np.ndarray
    ground_truth: Dict[str, Any]
    saturated_pixels: int
    warnings: List[str] = field(default_factory=list)
    stats: Dict[str, int] = field(default_factory=dict)

    def profile_frame(self):
        """The profile as a pandas DataFrame (needs pandas), equal to
        ``pandas.read_csv`` of the scan's ``pose_NNN_profile.csv``."""
        import pandas as pd

        return pd.DataFrame(self.profile)


class Scene:
    """A scene file loaded once: objects, materials, sensor, mount and scan settings, with its
    BVH built. Load with :meth:`load` or :meth:`from_toml`; the keywords override the file's
    settings exactly as the ``scan`` command's flags do (``scan_angle_deg`` is
    ``--scan-angle-deg``), with the same checks and messages.
    """

    def __init__(self, native: "_native.Scene"):
        if not isinstance(native, _native.Scene):
            raise TypeError(
                f"Scene({native!r}): load a scene with Scene.load(path or shipped name) or "
                "Scene.from_toml(text)"
            )
        self._native = native

    @classmethod
    def load(
        cls,
        path: PathLike,
        *,
        scan_angle_deg: Optional[float] = None,
        poses: Optional[int] = None,
        exposure_ms: Optional[float] = None,
        threshold: Union[int, str, None] = None,
        peak_select: Optional[str] = None,
        sensor_kind: Optional[str] = None,
    ) -> "Scene":
        """Loads the scene file at ``path`` (TOML), or a scene shipped in glassscan by its
        name (``Scene.load("edge_study")``; a file on disk of that name wins), as the command
        line's SCENE argument.

        Args:
            scan_angle_deg: scan angle above the surface's tangent plane, (0, 90].
            poses: number of scan poses along the target's border (1 to 10⁶).
            exposure_ms: exposure time (> 0).
            threshold: peak threshold in DN, or ``"auto"``.
            peak_select: ``all``, ``first``, ``last``, ``largest_area``, ``max_intensity``
                or ``single``.
            sensor_kind: ``cmos`` or ``ccd``.

        Raises:
            InputError: the file, a field or an override is not what it should be; the
                message names it (file:line:column for the scene file).
        """
        return cls._open(
            path, None, scan_angle_deg, poses, exposure_ms, threshold, peak_select, sensor_kind
        )

    @classmethod
    def _open(cls, path, text, scan_angle_deg, poses, exposure_ms, threshold, peak_select,
              sensor_kind) -> "Scene":
        return cls(
            _native.Scene.open(
                os.fspath(path),
                text,
                scan_angle_deg=scan_angle_deg,
                poses=poses,
                exposure_ms=exposure_ms,
                threshold=_threshold(threshold),
                peak_select=peak_select,
                sensor_kind=sensor_kind,
            )
        )

    @classmethod
    def from_toml(
        cls,
        text: str,
        *,
        path: PathLike = "<string>.toml",
        scan_angle_deg: Optional[float] = None,
        poses: Optional[int] = None,
        exposure_ms: Optional[float] = None,
        threshold: Union[int, str, None] = None,
        peak_select: Optional[str] = None,
        sensor_kind: Optional[str] = None,
    ) -> "Scene":
        """A scene from TOML text. ``path`` names it in messages and is where relative
        mesh paths start from (its directory); the keywords are those of :meth:`load`."""
        return cls._open(
            path, text, scan_angle_deg, poses, exposure_ms, threshold, peak_select, sensor_kind
        )

    @property
    def path(self) -> str:
        """The scene file (or the name given to :meth:`from_toml`)."""
        return os.fspath(self._native.path)

    @property
    def warnings(self) -> List[str]:
        """What the loader found suspicious but not wrong (the command line prints them as
        ``warning:`` lines), e.g. a mesh of implausible size, naming ``scale``."""
        return list(self._native.warnings)

    @property
    def target(self) -> Optional[str]:
        """The target object's name, or None if the scene has no ``[target]``."""
        return self._native.target

    @property
    def settings(self) -> Dict[str, Any]:
        """Scan angle (deg), standoff (mm), poses, exposure (ms), wavelength (nm), ADC bits,
        image shape (rows, columns) and points per profile, overrides applied."""
        return dict(self._native.settings)

    def scan_poses(self) -> List[Dict[str, Any]]:
        """The planned scan poses along the target's border (``scan``'s): ``index``,
        ``sensor_pose`` and ``flange_pose`` (4 × 4, mm), ``edge_point_mm``,
        ``border_fraction``."""
        return self._native.scan_poses()

    def __len__(self) -> int:
        """The number of planned scan poses."""
        return len(self._native.scan_poses())

    def simulate(
        self,
        pose: int = 0,
        *,
        photons: Union[int, str] = _native.DEFAULT_PHOTONS,
        seed: int = 1,
        max_depth: int = 64,
        threads: Optional[int] = None,
    ) -> Simulation:
        """Simulates the sensor at scan pose ``pose`` (an index into :meth:`scan_poses`): the
        same numbers, bit for bit, as ``glassscan scan SCENE --photons N --seed S`` writes for
        ``pose_NNN``, for any thread count. Releases the GIL while it runs.

        Args:
            photons: laser photons traced (1000 to 2⁴⁰; 2¹⁸, the default, is converged
                on the shipped pane at 10° and 40°, not by every criterion at 45°:
                validation/results/convergence in the repository), or ``"auto"``: the
                pose stops once its edge-line BIP has converged, after 2¹⁷ or 2¹⁸ photons
                (``stats["photons"]`` says how many), as ``--photons auto``.
            seed: master seed of every random number.
            max_depth: longest photon path, in surface interactions (1 to 4096).
            threads: worker threads (default: all cores); results do not depend on it.
        """
        raw = self._native.simulate(
            _whole("pose", pose),
            photons=None if photons == "auto" else _whole("photons", photons),
            seed=_whole("seed", seed),
            max_depth=_whole("max_depth", max_depth, 2**32 - 1),
            threads=None if threads is None else _whole("threads", threads),
        )
        truth = dict(raw["ground_truth"])
        truth["ideal_profile"] = ideal_table(truth["ideal_profile"])
        for key in ("edge_point_mm", "edge_point_sensor_mm"):
            if truth[key] is not None:
                truth[key] = np.array(truth[key], dtype=float)
        return Simulation(
            image=raw["image"],
            irradiance=raw["irradiance"],
            profile=profile_table(raw["profile"]),
            ground_truth=truth,
            saturated_pixels=raw["saturated_pixels"],
            warnings=list(raw["warnings"]),
            stats=json.loads(raw["stats_json"]),
        )

    def __repr__(self) -> str:
        s = self.settings
        return (
            f"Scene({self.path!r}, target={self.target!r}, poses={s['poses']}, "
            f"scan_angle_deg={s['scan_angle_deg']:g}, exposure_ms={s['exposure_ms']:g})"
        )


def _scene(scene: Union[Scene, PathLike]) -> Scene:
    return scene if isinstance(scene, Scene) else Scene.load(scene)


def locate(
    scene: Union[Scene, PathLike],
    *,
    poses: Optional[int] = None,
    scan_angle_deg: Optional[float] = None,
    perturb: Optional[Sequence[float]] = None,
    exposure_ms: Optional[float] = None,
    photons: Union[int, str] = _native.DEFAULT_PHOTONS,
    seed: int = 1,
    errors: str = "off",
    bip: str = "edge-line",
    opaque_copy: bool = False,
    opaque_exposure_ms: Optional[float] = None,
    out: Optional[PathLike] = None,
    force: bool = False,
) -> Dict[str, Any]:
    """The paper's pipeline, as ``glassscan locate SCENE --json``: scan the target's border
    from its nominal pose, a Border Identifier Point per profile, ICP of the BIPs against the
    model border, and the errors against ground truth. Returns the command's JSON summary
    (``bip_error_mm``, ``pose_error``, ``task_error_mm``, ``estimate`` with its
    ``matrix_mm`` as a 4 × 4 array, …).

    Args:
        scene: a :class:`Scene` (its overrides apply) or a scene file.
        perturb: the true pose relative to the nominal one, (dx, dy, dz) mm and
            (rx, ry, rz) deg.
        errors: ``off`` (the sensor alone) or ``default`` (robot, hand-eye, linearity).
        bip: ``edge-line`` or ``highest`` (the paper's rule); both are reported.
        out: also write the run's files (profiles, BIPs, poses, point clouds) there.
        The other keywords are the command's flags of the same name.
    """
    flags: List[str] = []

    def add(flag: str, value: Any) -> None:
        if value is not None:
            flags.extend([flag, str(value)])

    add("--poses", poses)
    add("--scan-angle-deg", None if scan_angle_deg is None else repr(float(scan_angle_deg)))
    if perturb is not None:
        values = [float(v) for v in perturb]
        flags.extend(["--perturb", ",".join(repr(v) for v in values)])
    add("--exposure-ms", None if exposure_ms is None else repr(float(exposure_ms)))
    add("--photons", photons)
    add("--seed", seed)
    add("--errors", errors)
    add("--bip", bip)
    if opaque_copy:
        flags.append("--opaque-copy")
    add(
        "--opaque-exposure-ms",
        None if opaque_exposure_ms is None else repr(float(opaque_exposure_ms)),
    )
    add("--out", None if out is None else os.fspath(out))
    if force:
        flags.append("--force")
    return _poses_to_arrays(json.loads(_scene(scene)._native.locate(flags)))


def register(model_scene: Union[Scene, PathLike], points: Any) -> Dict[str, Any]:
    """Registers your own border points to the model border of a scene's target by ICP from
    its nominal pose, as ``glassscan register MODEL_SCENE POINTS.csv --json``.

    Args:
        model_scene: a :class:`Scene` or a scene file with a ``[target]``.
        points: N × 3 array-like, base frame, mm (e.g. the BIPs of :func:`locate`'s
            ``out`` directory, or your own).

    Returns:
        The command's JSON result: ``estimate`` (translation_mm, rotation_deg, matrix_mm as a
        4 × 4 array, quaternion_wxyz), ``converged``, ``degenerate``, ``rms_mm``,
        ``condition``, ``iterations``, ``outlier_rows`` (indices into ``points``), and
        ``difference_from_scene_pose``.
    """
    array = np.ascontiguousarray(np.asarray(points, dtype=float))
    if array.ndim != 2 or array.shape[1] != 3:
        raise _native.InputError(
            f"points must be an N × 3 array of x, y, z in mm, got shape {array.shape}"
        )
    result = json.loads(_scene(model_scene)._native.register(array))
    result["outlier_rows"] = result.pop("outlier_lines")
    return _poses_to_arrays(result)
