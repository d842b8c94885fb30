"""The job engine: studies validated in the service (studies), computed on Dask (tasks, engine)."""
