"""Reading point tables: CSV with a header naming the columns (u,v,x,y[,z] in any order)."""
from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .models import CameraModelError


def read_columns(path: str | Path, names: Sequence[str]) -> np.ndarray:
    """The named columns of a CSV file as an (N, len(names)) float array.

    Blank lines and lines starting with # are skipped. Errors name the file and line."""
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as e:
        raise CameraModelError(f"cannot read {path}: {getattr(e, 'strerror', None) or e}") from None
    rows = [(n, r) for n, r in enumerate(csv.reader(text.splitlines()), start=1)
            if r and any(c.strip() for c in r) and not r[0].lstrip().startswith("#")]
    if not rows:
        raise CameraModelError(f"{path}: the file is empty (it needs a header {','.join(names)} and rows)")
    line, header = rows[0]
    header = [h.strip().lower() for h in header]
    missing = [n for n in names if n not in header]
    if missing:
        raise CameraModelError(f"{path}:{line}: the header must name the columns {','.join(names)} "
                               f"(missing {','.join(missing)}; found {','.join(header) or 'nothing'})")
    index = [header.index(n) for n in names]
    out = []
    for line, row in rows[1:]:
        if len(row) != len(header):
            raise CameraModelError(f"{path}:{line}: expected {len(header)} values, found {len(row)}")
        values = []
        for i in index:
            cell = row[i].strip()
            try:
                value = float(cell)
            except ValueError:
                raise CameraModelError(f"{path}:{line}: {cell!r} is not a number") from None
            if not math.isfinite(value):
                raise CameraModelError(f"{path}:{line}: {cell!r} is not a finite number")
            values.append(value)
        out.append(values)
    if not out:
        raise CameraModelError(f"{path}: no rows after the header")
    return np.array(out, dtype=float)
