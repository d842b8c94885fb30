"""Pure numerical core: imports nothing from the service, the CLI, pydantic or any web/database package."""
