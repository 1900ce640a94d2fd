"""Readers of the files glassscan writes, by the library's own readers (the ideal profile,
a plain CSV, by Python's csv module)."""

from __future__ import annotations

import csv
import os
from typing import Dict, Union

import numpy as np

from . import _native
from ._native import InputError
from ._tables import ideal_table, profile_table

PathLike = Union[str, "os.PathLike[str]"]


def read_image(path: PathLike) -> np.ndarray:
    """A sensor image ``.png`` as digital numbers (uint16, rows × columns, row 0 at the top):
    the file stores DN << (16 − adc_bits) and says so in its ``sBIT`` chunk, which this undoes."""
    return _native.read_image(os.fspath(path))


def read_irradiance(path: PathLike) -> Dict[str, np.ndarray]:
    """An irradiance ``.exr`` (W/m², float32): ``total`` and one layer per path class."""
    return _native.read_irradiance(os.fspath(path))


def read_profile(path: PathLike) -> np.ndarray:
    """A profile CSV as a structured array (see :data:`glassscan.PROFILE_DTYPE`)."""
    return profile_table(_native.read_profile(os.fspath(path)))


def read_points(path: PathLike) -> Dict[str, np.ndarray]:
    """A ``.ply`` point cloud: ``points`` (N × 3, mm), and ``colors``, ``label`` (index into
    :data:`glassscan.PATH_CLASSES`, 255 for none), ``intensity`` (DN) where present."""
    return _native.read_points(os.fspath(path))


_IDEAL_COLUMNS = ["ray", "fan_angle_deg", "x_mm", "z_mm", "object", "label", "part", "glass"]


def read_ideal_profile(path: PathLike) -> np.ndarray:
    """``ideal_profile.csv`` (the first hit of every fan ray, sensor frame, mm) as a
    structured array. Floats are written shortest-round-trip, so they read back exactly."""
    path = os.fspath(path)
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise InputError(f"could not read {path}: {e.strerror}") from None
    if not rows or rows[0] != _IDEAL_COLUMNS:
        found = ",".join(rows[0]) if rows else "an empty file"
        raise InputError(
            f"{path}: line 1: expected the header {','.join(_IDEAL_COLUMNS)}, found {found}"
        )
    columns: Dict[str, list] = {name: [] for name in _IDEAL_COLUMNS}
    parse = {
        "ray": int,
        "fan_angle_deg": float,
        "x_mm": float,
        "z_mm": float,
        "object": str,
        "label": str,
        "part": str,
        "glass": lambda s: {"true": True, "false": False}[s],
    }
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(_IDEAL_COLUMNS):
            raise InputError(
                f"{path}: line {number}: expected {len(_IDEAL_COLUMNS)} fields, found {len(row)}"
            )
        for name, field in zip(_IDEAL_COLUMNS, row):
            try:
                columns[name].append(parse[name](field))
            except (ValueError, KeyError):
                raise InputError(
                    f"{path}: line {number}, column {name}: cannot read {field!r}"
                ) from None
    return ideal_table(columns)
