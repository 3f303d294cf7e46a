"""Writing results: CSV with units in the header, PNG figures, markdown tables, Parquet with
units in the schema's metadata. The only module that writes CSV, PNG or Parquet files.

Every file is written under a temporary name beside its final one and renamed into place, so a
reader never sees half a file.
"""
from __future__ import annotations

import csv
import os
import uuid
from contextlib import contextmanager
from pathlib import Path

__all__ = ["header", "write_csv", "write_records", "read_csv", "markdown_table", "subplots",
           "save_png", "parquet_bytes", "write_parquet", "read_parquet", "with_units",
           "replaced", "UNITLESS"]

#: units written without a bracket in a CSV header
UNITLESS = ("", "-", "1", None)


@contextmanager
def replaced(path):
    """Yield a temporary path beside ``path``; rename it to ``path`` when the block ends
    without error, else remove it."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex}.tmp")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def header(names, units=None) -> list[str]:
    """Column titles ``name [unit]`` (no bracket for a unitless column)."""
    units = units or {}
    return [name if units.get(name) in UNITLESS else f"{name} [{units[name]}]"
            for name in names]


def _text(value) -> str:
    """A value at full precision: floats round-trip, booleans and integers as integers."""
    if value is None:
        return ""
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, int)) or getattr(value, "dtype", None) is not None and \
            value.dtype.kind in "biu":
        return str(int(value))
    return repr(float(value))


def write_csv(path, names, rows, units=None, titles=None) -> Path:
    """Write ``rows`` (sequences in the order of ``names``) with the header of
    :func:`header` (or ``titles`` as given: a format that fixes its header, e.g. the FMI
    cross-check files)."""
    with replaced(path) as tmp, open(tmp, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(titles if titles is not None else header(names, units))
        for row in rows:
            writer.writerow([_text(v) for v in row])
    return Path(path)


def write_records(path, records: list[dict], names=None, units=None) -> Path:
    """Write dicts as rows (``names``: the columns, default the first record's keys)."""
    names = list(names or (records[0] if records else ()))
    return write_csv(path, names, ([r.get(n, "") for n in names] for r in records), units)


def read_csv(path) -> dict:
    """A CSV written by :func:`write_csv`: column title -> list of its texts."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return {title: [r[k] for r in rows[1:]] for k, title in enumerate(rows[0])}


def markdown_table(titles, rows) -> str:
    """A markdown table: ``titles`` and rows of texts."""
    lines = ["| " + " | ".join(titles) + " |", "|" + "---|" * len(titles)]
    return "\n".join(lines + ["| " + " | ".join(map(str, row)) + " |" for row in rows])


def subplots(*args, **kwargs):
    """``matplotlib.pyplot.subplots`` on the Agg backend (no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt.subplots(*args, **kwargs)


def save_png(fig, path, dpi=110) -> Path:
    """Save ``fig`` as PNG at ``path`` and close it."""
    import matplotlib.pyplot as plt
    path = Path(path)
    try:
        with replaced(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format="png")
    finally:
        plt.close(fig)
    return path


def with_units(table, units: dict):
    """``table`` (pyarrow) with each column's unit in its field's metadata (``unit``)."""
    import pyarrow as pa
    fields = [f.with_metadata({"unit": units[f.name]}) if units.get(f.name) else f
              for f in table.schema]
    return table.cast(pa.schema(fields, metadata=table.schema.metadata))


def _encode(table, where) -> None:
    """Only the text columns are dictionary-encoded: tried on computed floats, a dictionary
    only grows until it is dropped (it made encoding 2.5 times slower and the file larger)."""
    import pyarrow as pa
    import pyarrow.parquet as pq
    text = [f.name for f in table.schema if pa.types.is_string(f.type)]
    pq.write_table(table, where, use_dictionary=text)


def parquet_bytes(table) -> bytes:
    """The Parquet file of ``table``, in memory (the bytes :func:`write_parquet` writes)."""
    import pyarrow as pa
    sink = pa.BufferOutputStream()
    _encode(table, sink)
    return sink.getvalue().to_pybytes()


def write_parquet(path, table=None, data: bytes | None = None) -> Path:
    """Write ``table`` (or a Parquet file's ``data``) at ``path``, whole or not at all."""
    with replaced(path) as tmp:
        if data is not None:
            Path(tmp).write_bytes(data)
        else:
            _encode(table, str(tmp))
    return Path(path)


def read_parquet(paths):
    """The rows of Parquet files, concatenated in the order given."""
    import pyarrow as pa
    import pyarrow.parquet as pq
    return pa.concat_tables([pq.read_table(p) for p in paths])
