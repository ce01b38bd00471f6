"""The REST/WebSocket API (FastAPI routers); the app in server/app.py mounts them."""
