"""A dataset made by ``glassscan dataset``, as a sequence of samples (a PyTorch map-style
dataset without depending on torch)."""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterator, List, Optional, Sequence, Union

import numpy as np

from . import _native
from ._files import read_ideal_profile, read_image, read_irradiance, read_points, read_profile
from ._native import InputError

PathLike = Union[str, "os.PathLike[str]"]

#: What a sample holds, by field, and the file each comes from.
FIELDS: Dict[str, str] = {
    "image": "image.png",
    "irradiance": "irradiance.exr",
    "profile": "profile.csv",
    "points": "points.ply",
    "ground_truth": "ground_truth.json",
    "ideal_profile": "ideal_profile.csv",
}

#: How many damage messages an error lists (it counts them all).
_LISTED = 10


def _ground_truth(path: str) -> Dict[str, Any]:
    try:
        with open(path, encoding="utf-8") as f:
            truth = json.load(f)
    except OSError as e:
        raise InputError(f"could not read {path}: {e.strerror}") from None
    except ValueError as e:
        raise InputError(f"{path}: not valid JSON: {e}") from None
    for value in truth.values():
        if isinstance(value, dict) and isinstance(value.get("matrix_mm"), list):
            value["matrix_mm"] = np.array(value["matrix_mm"], dtype=float).reshape(4, 4)
    for key in ("edge_point_mm", "edge_point_sensor_mm"):
        if truth.get(key) is not None:
            truth[key] = np.array(truth[key], dtype=float)
    return truth


#: The reader of each field's file.
_READERS = {
    "image": read_image,
    "irradiance": read_irradiance,
    "profile": read_profile,
    "points": read_points,
    "ground_truth": _ground_truth,
    "ideal_profile": read_ideal_profile,
}


class Dataset:
    """The samples of a dataset directory, in sample-index order.

    ``len(ds)``, ``ds[i]`` (also negative), ``ds[a:b]`` and iteration give samples as dicts:
    ``index``, ``manifest`` (its manifest line), and the fields of :data:`FIELDS` that
    ``fields`` asks for: ``image`` (uint16 DN), ``irradiance`` (dict of float32 W/m²),
    ``profile`` and ``ideal_profile`` (structured arrays), ``points`` (dict: ``points``
    N × 3 mm in the base frame, ``label``, ``intensity``, ``colors``), ``ground_truth``
    (dict; every pose's ``matrix_mm`` as a 4 × 4 array).

    Opening checks the dataset as ``glassscan verify`` does: every sample of the run listed
    once, every listed file present with its recorded size (``verify="sizes"``, one stat per
    file) or also its SHA-256 (``verify="hashes"``, reads every byte). Damage raises
    :class:`glassscan.InputError` naming the files. A dataset still being made (or a shard of
    one) opens with ``allow_missing=True``: its finished samples.

    The object holds only paths and manifest lines, so it pickles (PyTorch's DataLoader
    workers) and each worker reads its own files.
    """

    def __init__(
        self,
        path: PathLike,
        *,
        fields: Optional[Sequence[str]] = None,
        verify: str = "sizes",
        allow_missing: bool = False,
    ):
        if verify not in ("sizes", "hashes"):
            raise ValueError(f"verify must be 'sizes' or 'hashes', got {verify!r}")
        chosen = list(FIELDS) if fields is None else list(fields)
        unknown = [f for f in chosen if f not in FIELDS]
        if unknown:
            raise ValueError(f"unknown fields {unknown}; a sample has {list(FIELDS)}")
        self.path = os.fspath(path)
        self.fields: List[str] = chosen
        report_json, run_json, lines = _native.index_dataset(self.path, verify == "hashes")
        report = json.loads(report_json)
        problems = list(report["damage"])
        if report["duplicated"]:
            problems.append(f"samples listed more than once: {report['duplicated']}")
        if report["missing"] and not allow_missing:
            first = report["missing_first"]
            more = ", …" if report["missing"] > len(first) else ""
            problems.append(
                f"{report['missing']} of {report['count']} samples are in no manifest "
                f"({', '.join(map(str, first))}{more}); pass allow_missing=True to open the "
                "finished ones"
            )
        if problems:
            listed = "; ".join(problems[:_LISTED])
            more = f"; and {len(problems) - _LISTED} more" if len(problems) > _LISTED else ""
            raise InputError(f"{self.path}: the dataset is damaged: {listed}{more}")
        #: ``run.json``: how the dataset was made (scene text, seed, photons, count).
        self.run: Dict[str, Any] = json.loads(run_json)
        entries = [json.loads(line) for line in lines]
        entries.sort(key=lambda e: e["index"])
        #: The manifest lines, in sample-index order.
        self.manifest: List[Dict[str, Any]] = entries

    def __len__(self) -> int:
        return len(self.manifest)

    @property
    def indices(self) -> np.ndarray:
        """The sample index of each position."""
        return np.array([e["index"] for e in self.manifest], dtype=np.uint64)

    def sample_dir(self, i: int) -> str:
        """The directory of the sample at position ``i``."""
        return os.path.join(self.path, self.manifest[self._position(i)]["directory"])

    def _position(self, i: int) -> int:
        n = len(self.manifest)
        if not isinstance(i, (int, np.integer)):
            raise TypeError(f"a dataset is indexed by int or slice, got {type(i).__name__}")
        k = int(i) + n if i < 0 else int(i)
        if not 0 <= k < n:
            raise IndexError(f"sample position {i} is outside 0..{n}")
        return k

    def __getitem__(self, i: Union[int, slice]) -> Any:
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        entry = self.manifest[self._position(i)]
        directory = os.path.join(self.path, entry["directory"])
        sample: Dict[str, Any] = {"index": entry["index"], "manifest": entry}
        for name in self.fields:
            sample[name] = _READERS[name](os.path.join(directory, FIELDS[name]))
        return sample

    def __iter__(self) -> Iterator[Dict[str, Any]]:
        for k in range(len(self)):
            yield self[k]

    def __repr__(self) -> str:
        return f"Dataset({self.path!r}, samples={len(self)}, fields={self.fields})"
