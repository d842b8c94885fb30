"""The web service around the numerical core: FastAPI app, SQLAlchemy store, Dask job engine.

`create_app(load_settings())` builds the app; `footprint serve` runs it. Nothing here is imported by the core.
"""
