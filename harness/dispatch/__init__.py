"""Running scripts in numbers: the worker pool and the Dask cluster, over the runners of harness/sut/."""
