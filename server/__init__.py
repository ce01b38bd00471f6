"""The service side: archive, command-line entry point, benchmark (and, with
the console issue, the FastAPI app and the background simulation service)."""
