"""A study's table as files: CSV (always) and Parquet (with pyarrow, the ``[dask]`` extra).

Both hold the same columns in the same order (:class:`cam_workbench.generators.studies.table.StudyTable`).
CSV: a header row, numbers written exactly (``repr`` of the float: read back bit for bit),
booleans as ``true``/``false``, an empty cell where a row has no value.  Parquet: a column of
numbers is float64 (int64 when every value is whole and was given as an integer), of booleans
bool, anything else string, missing values null; the study's ``meta`` (kind, grid, settings) is
the schema's ``cam_workbench`` metadata, as JSON.
"""
from __future__ import annotations

import csv
import io
import json
import math
from typing import Any

from cam_workbench.generators.studies.table import StudyTable


def _cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
    return str(v)


def csv_text(table: StudyTable) -> str:
    """The table as CSV text."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(table.columns)
    for row in table.rows:
        w.writerow([_cell(row.get(c)) for c in table.columns])
    return buf.getvalue()


def have_parquet() -> bool:
    """pyarrow is importable (Parquet can be written)."""
    try:
        import pyarrow  # noqa: F401  (deferred: pyarrow, of the [dask] extra)
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


def _arrow_column(values: list[Any]) -> Any:
    import pyarrow as pa  # deferred: pyarrow, of the [dask] extra

    present = [v for v in values if v is not None]
    if present and all(isinstance(v, bool) for v in present):
        return pa.array(values, type=pa.bool_())
    if present and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in present):
        if all(isinstance(v, int) for v in present):
            return pa.array(values, type=pa.int64())
        return pa.array([None if v is None else float(v) for v in values], type=pa.float64())
    return pa.array([None if v is None else str(v) for v in values], type=pa.string())


def parquet_bytes(table: StudyTable) -> bytes:
    """The table as a Parquet file (needs pyarrow)."""
    import pyarrow as pa  # deferred: pyarrow, of the [dask] extra
    import pyarrow.parquet as pq

    arrays = [_arrow_column(table.column(c)) for c in table.columns]
    t = pa.table(arrays, names=list(table.columns))
    t = t.replace_schema_metadata({"cam_workbench": json.dumps(table.meta, default=str)})
    sink = pa.BufferOutputStream()
    pq.write_table(t, sink)
    return sink.getvalue().to_pybytes()


def meta_text(table: StudyTable) -> str:
    """The study's ``meta`` as JSON text (study.json)."""
    return json.dumps(table.meta, indent=1, default=str) + "\n"
