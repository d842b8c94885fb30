"""The map page's files (frontend/), as the app serves them at "/"."""

from pathlib import PurePath

from fastapi.staticfiles import StaticFiles
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.types import Scope


class PageFiles(StaticFiles):
    """The page's own files of frontend/ and nothing else there (node_modules, package files, scripts, README): its
    index.html and styles.css, its modules in js/, and vendor/, the built third-party files it and /docs load."""

    FILES, DIRS = {".", "index.html", "styles.css"}, {"js", "vendor"}

    async def get_response(self, path: str, scope: Scope):
        if path not in self.FILES and PurePath(path).parts[0] not in self.DIRS:  # path: normalized, relative
            raise StarletteHTTPException(status_code=404)
        return await super().get_response(path, scope)
