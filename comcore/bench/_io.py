"""Result files: JSON lines (no dependency) or Parquet (pyarrow), and the paper's tables."""

from __future__ import annotations

import csv
import io
import json
from functools import cache
from importlib import resources
from pathlib import Path

from ._trial import ROW_FIELDS

__all__ = ["FORMATS", "paper_table", "read_rows", "write_rows"]

#: Result file formats by suffix.
FORMATS = {".jsonl": "jsonl", ".parquet": "parquet"}


def _format_of(path: Path) -> str:
    if path.suffix not in FORMATS:
        raise ValueError(f"path must end with one of {sorted(FORMATS)}, got {str(path)!r}")
    return FORMATS[path.suffix]


def write_rows(rows, path) -> Path:
    """Write result rows to ``path`` (``.jsonl`` or ``.parquet``, chosen by suffix).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> row = {k: 0 for k in ROW_FIELDS} | {"object": "Obj1", "estimator": "alg2"}
    >>> path = write_rows([row], pathlib.Path(tempfile.mkdtemp()) / "r.jsonl")
    >>> read_rows(path)[0]["object"]
    'Obj1'
    """
    path = Path(path)
    kind = _format_of(path)
    rows = [{key: row[key] for key in ROW_FIELDS} for row in rows]
    path.parent.mkdir(parents=True, exist_ok=True)
    if kind == "jsonl":
        with path.open("w", encoding="utf-8") as f:
            for row in rows:
                f.write(json.dumps(row, allow_nan=False) + "\n")
        return path
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError as e:
        raise ImportError("Parquet output needs pyarrow: pip install comcore[bench]") from e
    columns = {key: [row[key] for row in rows] for key in ROW_FIELDS}
    pq.write_table(pa.table(columns), path)
    return path


def read_rows(path) -> list[dict]:
    """Read rows written by :func:`write_rows`."""
    path = Path(path)
    if _format_of(path) == "jsonl":
        with path.open(encoding="utf-8") as f:
            return [json.loads(line) for line in f if line.strip()]
    try:
        import pyarrow.parquet as pq
    except ImportError as e:
        raise ImportError("reading Parquet needs pyarrow: pip install comcore[bench]") from e
    return pq.read_table(path).to_pylist()


def _number(text: str) -> float:
    value = float(text)
    return int(value) if value.is_integer() and "." not in text else value


@cache
def _paper_csv(name: str) -> tuple[dict, ...]:
    text = (resources.files("comcore") / "data" / name).read_text(encoding="utf-8")
    reader = csv.DictReader(io.StringIO(text))
    return tuple(
        {k: (v if k == "object" else _number(v)) for k, v in row.items()} for row in reader
    )


def paper_table(number: int) -> dict[str, dict]:
    """The paper's Table I (Alg. 1) or II (Alg. 2), keyed by object name.

    Values are in cm (errors), cm^2 (``size_cm2``) and pushes; the columns are
    those of ``comcore/data/paper_table{1,2}.csv``.

    Examples
    --------
    >>> paper_table(1)["Obj1"]["low_mean_cm"]
    0.742
    >>> paper_table(2)["Obj20"]["high_push_max"]
    6
    """
    if number not in (1, 2):
        raise ValueError(f"number must be 1 or 2, got {number!r}")
    rows = _paper_csv(f"paper_table{number}.csv")
    return {row["object"]: dict(row) for row in rows}
