"""``pipeplug sweep``: grids and random samples of single blows or whole drives, run through the
core in chunks on a Dask cluster (this machine by default), results as Parquet; the engine
(:mod:`.engine`) also runs other campaigns (fuzz runs)."""
