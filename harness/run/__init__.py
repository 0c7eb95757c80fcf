"""Running scripts: the executive, the worker pool, the Dask cluster; external SUTs in run/external/."""
