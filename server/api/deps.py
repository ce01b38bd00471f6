"""Dependencies shared by the routers: the service, operator authentication,
and read-only archive connections for API threads."""
from __future__ import annotations

import secrets
import sqlite3
import threading
from pathlib import Path
from typing import Annotated

from fastapi import Depends, HTTPException, Request, status
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from server.archive import Archive
from server.service import SimService

_bearer = HTTPBearer(auto_error=False, description="the operator token (ACS_TOKEN)")


def get_service(request: Request) -> SimService:
    return request.app.state.service


def require_operator(request: Request,
                     creds: Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)]) -> str:
    """Anything that commands needs the operator token; viewing does not.
    401 when no token was sent, 403 when it is wrong (RFC 6750 / RFC 9110)."""
    if creds is None or creds.scheme.lower() != "bearer":
        raise HTTPException(status.HTTP_401_UNAUTHORIZED, "operator token required (Authorization: Bearer ...)",
                            headers={"WWW-Authenticate": "Bearer"})
    if not secrets.compare_digest(creds.credentials.encode(), request.app.state.token.encode()):
        raise HTTPException(status.HTTP_403_FORBIDDEN, "wrong operator token")
    return "rest"


_local = threading.local()


def reader(path: Path) -> Archive:
    """A read-only Archive on this thread's own connection: SQLite connections
    belong to one thread, and WAL lets readers run beside the writer. Opened
    read-only so that a reader never takes the write lock (Archive() would,
    to create its tables)."""
    cache = getattr(_local, "archives", None)
    if cache is None:
        cache = _local.archives = {}
    archive = cache.get(path)
    if archive is None:
        archive = Archive.__new__(Archive)
        archive.path = path
        archive.db = sqlite3.connect(f"file:{path}?mode=ro", uri=True, check_same_thread=False)
        cache[path] = archive
    return archive


def get_reader(service: Annotated[SimService, Depends(get_service)]) -> Archive:
    return reader(service.archive_path)


# FastAPI's Annotated dependencies: the routes' parameters
Service = Annotated[SimService, Depends(get_service)]
Operator = Annotated[str, Depends(require_operator)]
Reader = Annotated[Archive, Depends(get_reader)]
