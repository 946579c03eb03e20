"""``report.json``: the design's numbers (its keys: docs/cli.md) plus the files written."""
from __future__ import annotations

import json
import math
from typing import Any


def _clean(v: Any) -> Any:
    if isinstance(v, dict):
        return {k: _clean(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_clean(x) for x in v]
    if hasattr(v, "item") and callable(v.item):  # numpy scalar
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v


def report_json_text(summary: dict[str, Any], files: dict[str, str] | None = None) -> str:
    """The report as JSON text (NaN/inf become null so every JSON reader accepts it)."""
    data = dict(summary)
    if files is not None:
        data["files"] = dict(files)
    return json.dumps(_clean(data), indent=2, ensure_ascii=False) + "\n"
