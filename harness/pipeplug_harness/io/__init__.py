"""What the harness writes, and where: files (:mod:`.files`: CSV with units in the header, PNG,
markdown tables, Parquet with units in the schema) and output folders that never lose data
(:mod:`.folder`)."""
from .files import (
    header,
    markdown_table,
    parquet_bytes,
    read_csv,
    read_parquet,
    replaced,
    save_png,
    subplots,
    with_units,
    write_csv,
    write_parquet,
    write_records,
)
from .folder import LOCK, MANIFEST, OutputFolder, foreign, listed

__all__ = ["header", "markdown_table", "parquet_bytes", "read_csv", "read_parquet", "replaced",
           "save_png", "subplots", "with_units", "write_csv", "write_parquet", "write_records",
           "OutputFolder", "MANIFEST", "LOCK", "foreign", "listed"]
