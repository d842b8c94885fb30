"""Storage: SQLAlchemy 2 models (models), engine and migrations (engine), every query (queries)."""
