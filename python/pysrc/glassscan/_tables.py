"""The tables glassscan writes as CSV, as numpy structured arrays with the same column names
(every physical column ends in its unit: ``_mm``, ``_px``, ``_dn``, ``_dn_px``)."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from . import _native

#: Path class names, in the order of the ``label`` numbers of ``points.ply`` (255: none).
PATH_CLASSES: tuple[str, ...] = tuple(_native.path_classes())

_LABEL = f"U{max(len(n) for n in PATH_CLASSES)}"

#: One measured profile point: the firmware's per-peak record, its path class and flags.
#: Invalid points hold NaN in ``row_px``, ``x_mm`` and ``z_mm``.
PROFILE_DTYPE = np.dtype(
    [
        ("column", "u4"),
        ("reflection", "u1"),
        ("row_px", "f8"),
        ("x_mm", "f8"),
        ("z_mm", "f8"),
        ("intensity_dn", "u2"),
        ("width_px", "u4"),
        ("threshold_dn", "u2"),
        ("m0_dn", "f8"),
        ("m1_dn_px", "f8"),
        ("label", _LABEL),
        ("valid", "?"),
        ("saturated", "?"),
    ]
)


def ideal_profile_dtype(object_names: Sequence[str]) -> np.dtype:
    """The ideal profile's dtype; the object column is as wide as the longest name."""
    width = max([1, *(len(n) for n in object_names)])
    return np.dtype(
        [
            ("ray", "u4"),
            ("fan_angle_deg", "f8"),
            ("x_mm", "f8"),
            ("z_mm", "f8"),
            ("object", f"U{width}"),
            ("label", "U16"),
            ("part", "U16"),
            ("glass", "?"),
        ]
    )


#: The ideal profile's dtype for object names of up to 32 characters (the first fan-ray hits,
#: sensor frame, mm); a table's own dtype is as wide as its longest object name.
IDEAL_PROFILE_DTYPE = ideal_profile_dtype(["x" * 32])


def structured(columns: Mapping[str, Sequence], dtype: np.dtype) -> np.ndarray:
    """The structured array of ``dtype`` whose fields are ``columns`` (all of one length)."""
    n = len(columns[dtype.names[0]])
    table = np.empty(n, dtype=dtype)
    for name in dtype.names:
        table[name] = columns[name]
    return table


def profile_table(columns: Mapping[str, Sequence]) -> np.ndarray:
    """A profile as a structured array of :data:`PROFILE_DTYPE`."""
    return structured(columns, PROFILE_DTYPE)


def ideal_table(columns: Mapping[str, Sequence]) -> np.ndarray:
    """An ideal profile as a structured array."""
    return structured(columns, ideal_profile_dtype(columns["object"]))
